#include "runtime/live_parameters.hpp"

#include <fmt/format.h>

#include <cmath>

#include "core/error.hpp"

namespace tactus::runtime {

LiveParameters::LiveParameters(const scene::Model& model)
    : scene_source_(model.source), body_count_(model.bodies.size()), device_count_(model.devices.size()) {
  for (std::size_t i = 0; i < model.bodies.size() && i < kMaxBodies; ++i) {
    const scene::Body& b = model.bodies[i];
    body_names_[i] = b.name;
    const bool deformable = b.kind != scene::BodyKind::rigid && b.kind != scene::BodyKind::embedded && !b.cspace;
    if (!deformable || !b.material) continue;
    const scene::Material& m = model.materials.at(*b.material);
    Material& out = scene_materials_.body[i];
    out.young_modulus = m.young_modulus;
    // The panel's starting value: the scene's damping per unit mass (uniform except for
    // surface springs, whose nodal damping is shown over the mean node mass).
    double alpha = m.damping.rayleigh_alpha;
    if (b.kind == scene::BodyKind::tet_mass_spring && b.volume && !b.volume->vertices.empty()) {
      const double mean_mass = m.density * b.volume->volume() / static_cast<double>(b.volume->vertices.size());
      if (mean_mass > 0.0) alpha += m.damping.nodal / mean_mass;
    } else if (b.kind == scene::BodyKind::surface_mass_spring && !b.surface.vertices.empty()) {
      double area = 0.0;
      for (const auto& t : b.surface.triangles)
        area += 0.5 * (b.surface.vertices[static_cast<std::size_t>(t[1])] - b.surface.vertices[static_cast<std::size_t>(t[0])])
                          .cross(b.surface.vertices[static_cast<std::size_t>(t[2])] -
                                 b.surface.vertices[static_cast<std::size_t>(t[0])])
                          .norm();
      const double mean_mass = m.density * b.thickness * area / static_cast<double>(b.surface.vertices.size());
      alpha = mean_mass > 0.0 ? m.damping.nodal / mean_mass : 0.0;
    }
    out.damping = alpha;
  }
  edited_materials_ = scene_materials_;
  materials_.store(scene_materials_);
}

void LiveParameters::set_material(std::size_t body, double young_modulus, double damping, double from) {
  const SourceLocation where{scene_source_, {}, {}, {}};
  if (body >= body_count_) throw InputError(where, fmt::format("live edit: no body {} in the scene", body));
  if (!material_editable(body))
    throw InputError(where, fmt::format("live edit: body '{}' has no material that can be edited (rigid, cspace, "
                                        "embedded, or beyond the first {} bodies)",
                                        body_names_[body], kMaxBodies));
  if (!(young_modulus > 0.0 && std::isfinite(young_modulus)))
    throw InputError(where, fmt::format("live edit: body '{}': Young's modulus must be positive, not {}",
                                        body_names_[body], young_modulus));
  if (!std::isfinite(damping))
    throw InputError(where, fmt::format("live edit: body '{}': damping must be finite", body_names_[body]));
  Material& m = edited_materials_.body[body];
  m.young_modulus = young_modulus;
  m.damping_set = damping >= 0.0;
  if (m.damping_set) m.damping = damping;
  ++edited_materials_.version;
  edited_materials_.from = from;
  materials_.store(edited_materials_);
}

void LiveParameters::set_surface(std::size_t device, double stiffness, double static_friction,
                                 double kinetic_friction, double from) {
  const SourceLocation where{scene_source_, {}, {}, {}};
  if (device >= device_count_ || device >= kMaxDevices)
    throw InputError(where, fmt::format("live edit: no editable device {} in the scene", device));
  const SurfaceKind kind = surface_kind(device);
  if (kind == SurfaceKind::none)
    throw InputError(where, fmt::format("live edit: device {}'s contact has no stiffness to edit (Hertz, fingerpad, "
                                        "needle, multi-surface or configuration-space contact)",
                                        device));
  if (!(stiffness > 0.0 && stiffness <= max_stiffness_[device]))
    throw InputError(where, fmt::format("live edit: device {}: stiffness {} N/m outside (0, {}] (the device's "
                                        "max_stiffness)",
                                        device, stiffness, max_stiffness_[device]));
  if (!(static_friction >= 0.0 && kinetic_friction >= 0.0 && kinetic_friction <= static_friction &&
        std::isfinite(static_friction)))
    throw InputError(where, fmt::format("live edit: device {}: friction needs 0 ≤ μk ≤ μs (μs = {}, μk = {})", device,
                                        static_friction, kinetic_friction));
  if (kind != SurfaceKind::proxy && (static_friction != 0.0 || kinetic_friction != 0.0))
    throw InputError(where, fmt::format("live edit: device {}: a penalty contact has no friction", device));
  Surface& s = edited_surfaces_[device];
  s.stiffness = stiffness;
  s.static_friction = static_friction;
  s.kinetic_friction = kinetic_friction;
  ++s.version;
  s.from = from;
  surfaces_[device].store(s);
}

void LiveParameters::describe_device(std::size_t device, const haptics::HapticModel& model, double max_stiffness) {
  if (device >= kMaxDevices) return;
  // Only a proxy or a penalty coupling has a stiffness to edit: the other algorithms' force
  // comes from the tissue or from their own law.
  const haptics::ForceAlgorithm* contact = model.contact();
  const haptics::EditableSurface editable = contact ? contact->editable_surface() : haptics::EditableSurface{};
  Surface s;
  SurfaceKind kind = SurfaceKind::none;
  if (editable.kind != haptics::EditableSurface::Kind::none) {
    kind = editable.kind == haptics::EditableSurface::Kind::proxy ? SurfaceKind::proxy : SurfaceKind::penalty;
    s.stiffness = editable.values.stiffness;
    s.static_friction = editable.values.static_friction;
    s.kinetic_friction = editable.values.kinetic_friction;
  }
  surface_kinds_[device] = kind;
  scene_surfaces_[device] = s;
  edited_surfaces_[device] = s;
  max_stiffness_[device] = max_stiffness;
  surfaces_[device].store(s);
}

VecX scene_mass_damping(const scene::Model& model, std::size_t index, const VecX& lumped_mass) {
  const scene::Body& b = model.bodies.at(index);
  VecX c = VecX::Zero(lumped_mass.size());
  if (!b.material) return c;
  const scene::Material& m = model.materials.at(*b.material);
  switch (b.kind) {
    case scene::BodyKind::fem: c.setConstant(m.damping.rayleigh_alpha); break;
    case scene::BodyKind::tet_mass_spring: {
      // As compile/bodies.cpp builds it: d_i = α m_i with α = Rayleigh α + nodal / mean mass.
      const double mean_mass = m.density * b.volume->volume() / static_cast<double>(b.volume->vertices.size());
      c.setConstant(m.damping.rayleigh_alpha + (mean_mass > 0.0 ? m.damping.nodal / mean_mass : 0.0));
      break;
    }
    case scene::BodyKind::surface_mass_spring:
      for (Eigen::Index i = 0; i < c.size(); ++i) c[i] = lumped_mass[i] > 0.0 ? m.damping.nodal / lumped_mass[i] : 0.0;
      break;
    case scene::BodyKind::rigid:
    case scene::BodyKind::embedded:
    case scene::BodyKind::cloth: break;
  }
  return c;
}

// --- LiveMaterialModel ---------------------------------------------------------------------

namespace {

struct LiveScratch final : physics::Scratch {
  std::unique_ptr<physics::Scratch> inner;
  mutable VecX scaled;  ///< a scaled copy of an argument (sized once)
};

physics::Scratch& inner_of(physics::Scratch& s) { return *static_cast<LiveScratch&>(s).inner; }
const physics::Scratch& inner_of(const physics::Scratch& s) { return *static_cast<const LiveScratch&>(s).inner; }
const VecX& scaled_copy(const physics::Scratch& s, double scale, const VecX& in) {
  VecX& out = static_cast<const LiveScratch&>(s).scaled;
  out.resize(in.size());  // a no-op after the first call
  out = scale * in;
  return out;
}

}  // namespace

LiveMaterialModel::LiveMaterialModel(std::shared_ptr<const physics::ForceModel> inner, VecX scene_damping)
    : inner_(std::move(inner)), scene_damping_(std::move(scene_damping)) {
  extra_ = VecX::Zero(scene_damping_.size());
}

void LiveMaterialModel::set(double scale, double damping) {
  scale_ = scale;
  const VecX& m = inner_->lumped_mass();
  has_extra_ = false;
  for (Eigen::Index i = 0; i < extra_.size(); ++i) {
    const double target = damping >= 0.0 ? damping : scene_damping_[i];
    extra_[i] = (target - scale * scene_damping_[i]) * m[i];
    has_extra_ = has_extra_ || extra_[i] != 0.0;
  }
}

std::unique_ptr<physics::Scratch> LiveMaterialModel::make_scratch() const {
  auto s = std::make_unique<LiveScratch>();
  s->inner = inner_->make_scratch();
  s->scaled = VecX::Zero(static_cast<Eigen::Index>(3 * inner_->node_count()));
  return s;
}

void LiveMaterialModel::forces(const VecX& x, const VecX& v, const VecX& q, VecX& f, physics::Scratch& s) const {
  inner_->forces(x, v, q, f, inner_of(s));
  if (scale_ != 1.0) f *= scale_;
  if (has_extra_ && v.size() == f.size()) f -= extra_.cwiseProduct(v);
}

void LiveMaterialModel::linearize(const VecX& x, const VecX& v, const VecX& q, physics::Scratch& s) const {
  inner_->linearize(x, v, q, inner_of(s));
}

void LiveMaterialModel::add_stiffness_product(const VecX& dx, VecX& out, const physics::Scratch& s) const {
  inner_->add_stiffness_product(scale_ == 1.0 ? dx : scaled_copy(s, scale_, dx), out, inner_of(s));
}

void LiveMaterialModel::add_damping_product(const VecX& dv, VecX& out, const physics::Scratch& s) const {
  inner_->add_damping_product(scale_ == 1.0 ? dv : scaled_copy(s, scale_, dv), out, inner_of(s));
  if (has_extra_) out += extra_.cwiseProduct(dv);
}

void LiveMaterialModel::add_system_product(double a_mass, double b_damping, double c_stiffness, const VecX& in,
                                           VecX& out, const physics::Scratch& s) const {
  inner_->add_system_product(a_mass, scale_ * b_damping, scale_ * c_stiffness, in, out, inner_of(s));
  if (has_extra_ && b_damping != 0.0) out += b_damping * extra_.cwiseProduct(in);
}

void LiveMaterialModel::add_diagonal(double a, double b, VecX& out, const physics::Scratch& s) const {
  inner_->add_diagonal(scale_ * a, scale_ * b, out, inner_of(s));
  if (has_extra_ && b != 0.0) out += b * extra_;
}

const physics::BlockMatrix* LiveMaterialModel::assemble_system(double a, double b, double c, physics::Scratch& s) const {
  const physics::BlockMatrix* m = inner_->assemble_system(a, scale_ * b, scale_ * c, inner_of(s));
  if (m && has_extra_ && b != 0.0) {
    // The matrix lives in the inner model's scratch, which this call owns until the next one.
    auto& diagonal = const_cast<physics::BlockMatrix*>(m)->diagonal;
    for (std::size_t n = 0; n < diagonal.size(); ++n)
      for (int k = 0; k < 3; ++k) diagonal[n](k, k) += b * extra_[static_cast<Eigen::Index>(3 * n) + k];
  }
  return m;
}

void LiveMaterialModel::linearized_forces(const VecX& x, const VecX& v, const VecX& q, const VecX& dx, VecX& f,
                                          physics::Scratch& s) const {
  // scale · (f + K dx) = (scale·f) + (scale·K) dx.
  inner_->linearized_forces(x, v, q, dx, f, inner_of(s));
  if (scale_ != 1.0) f *= scale_;
  if (has_extra_ && v.size() == f.size()) f -= extra_.cwiseProduct(v);
}

void LiveMaterialModel::add_triplets(double a, double b, std::vector<physics::Triplet>& out,
                                     const physics::Scratch& s) const {
  inner_->add_triplets(scale_ * a, scale_ * b, out, inner_of(s));
  if (has_extra_ && b != 0.0)
    for (Eigen::Index i = 0; i < extra_.size(); ++i)
      if (extra_[i] != 0.0) out.emplace_back(i, i, b * extra_[i]);
}

bool LiveMaterialModel::add_matrix_values(double a, double b, double mass, std::span<const std::int32_t> slots,
                                          double* values, const physics::Scratch& s) const {
  // The added damping's triplets come between the model's and the mass's, and their number
  // follows the edits: those matrices are assembled from triplets.
  if (has_extra_ && b != 0.0) return false;
  return inner_->add_matrix_values(scale_ * a, scale_ * b, mass, slots, values, inner_of(s));
}

void LiveMaterialModel::update_internal(const VecX& x, double dt, VecX& q, physics::Scratch& s) const {
  inner_->update_internal(x, dt, q, inner_of(s));
}

double LiveMaterialModel::elastic_energy(const VecX& x, const VecX& q) const {
  return scale_ * inner_->elastic_energy(x, q);
}

// --- the loops' side -------------------------------------------------------------------------

}  // namespace tactus::runtime
