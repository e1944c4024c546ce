#include "fitting/indentation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "core/error.hpp"
#include "mesh/generators.hpp"
#include "mesh/io/mesh_io.hpp"
#include "physics/body.hpp"
#include "physics/fem/tet_fem.hpp"
#include "physics/mass_spring/tet_builder.hpp"

namespace tactus::fitting {
namespace {

/// y at x, as a power law (a line in log–log) between the samples that bracket x; below the
/// first or past the last, the first's or the last's pair's law. xs increase, every x and y
/// positive.
double power_law_between(std::span<const double> xs, std::span<const double> ys, double x) {
  if (!(x > 0.0)) return 0.0;
  std::size_t k = 1;
  while (k + 1 < xs.size() && xs[k] < x) ++k;
  const double slope = std::log(ys[k] / ys[k - 1]) / std::log(xs[k] / xs[k - 1]);
  return ys[k - 1] * std::pow(x / xs[k - 1], slope);
}

/// Ramp steps of a relaxation's loading (the hereditary integral's quadrature).
constexpr int kRampSteps = 10;
/// A creep's elastic curve: depths pressed up to its limit; its quadrature's ramp steps and
/// most steps.
constexpr int kCreepDepths = 12;
constexpr int kCreepRampSteps = 50;
constexpr double kCreepMaxSteps = 20000;
/// Halvings of a depth step whose static solve fails before the forward model gives up.
constexpr int kMaxHalvings = 6;
/// Active-set passes of the sphere's contact at one depth.
constexpr int kMaxActiveSetPasses = 30;
/// Newton's tolerance, relative to the forces: the curve is this accurate, far below the
/// Jacobian's step (fit.hpp, kJacobianStep) and any measurement's noise.
constexpr double kNewtonTolerance = 1e-8;

double horizontal_distance(const Vec3& p, const Vec3& axis) { return std::hypot(p.x() - axis.x(), p.y() - axis.y()); }

/// One pressing of the specimen: the body, its supports and the contact set.
class Press {
 public:
  Press(const IndentationModel& model, const Experiment& e, const Vec3& top_centre, const std::vector<std::int32_t>& top,
        const std::vector<std::int32_t>& bottom, const physics::FemMaterial& material)
      : e_(e), top_centre_(top_centre), top_(top) {
    physics::FemMaterial elastic = material;
    elastic.prony.clear();  // relaxation is the hereditary integral's, not the body's
    if (e.mass_spring) {
      // The scene's tet_mass_spring body at its instantaneous stiffness: every spring
      // k = E Σ V_t / l² (physics/mass_spring/tet_builder.hpp).
      physics::TetSpringParams springs;
      springs.youngs_modulus = elastic.young_modulus;
      springs.density = elastic.density;
      body_.model = physics::tet_mass_spring(model.mesh(), springs);
    } else {
      body_.model = std::make_shared<physics::TetFem>(model.mesh(), elastic);
    }
    body_.settings.solver = physics::LinearSolver::cholesky;
    const std::size_t n = model.mesh().vertices.size();
    body_.fixed_dofs.assign(3 * n, 0);
    for (auto b : bottom) {
      const auto i = 3 * static_cast<std::size_t>(b);
      body_.fixed_dofs[i + 2] = 1;
      if (e.specimen.bottom == Support::fixed) body_.fixed_dofs[i] = body_.fixed_dofs[i + 1] = 1;
    }
    if (e.specimen.bottom == Support::sliding) {
      // A sliding base leaves the block free to shift and turn in its plane: pin the bottom
      // node nearest the axis in x and y, and the one farthest along +x in y (both carry no
      // load in a symmetric press).
      std::int32_t centre = bottom.front(), far = bottom.front();
      const auto& v = model.mesh().vertices;
      for (auto b : bottom) {
        const auto k = static_cast<std::size_t>(b);
        if (horizontal_distance(v[k], top_centre) < horizontal_distance(v[static_cast<std::size_t>(centre)], top_centre))
          centre = b;
        if (v[k].x() > v[static_cast<std::size_t>(far)].x()) far = b;
      }
      body_.fixed_dofs[3 * static_cast<std::size_t>(centre)] = 1;
      body_.fixed_dofs[3 * static_cast<std::size_t>(centre) + 1] = 1;
      body_.fixed_dofs[3 * static_cast<std::size_t>(far) + 1] = 1;
    }
    support_ = body_.fixed_dofs;
    state_ = physics::make_state(body_);
    rest_ = state_.x;
    equilibrium_ = rest_;
    in_contact_.assign(top_.size(), 0);
    if (!e.indenter.round()) {
      for (std::size_t k = 0; k < top_.size(); ++k)
        in_contact_[k] = horizontal_distance(node_rest(top_[k]), top_centre_) <= e.indenter.radius * (1 + 1e-9);
      apply_contact_set();
    }
  }

  /// Presses from the last equilibrium to `depth`, halving the step where a solve fails.
  /// Returns the force on the indenter.
  double press_to(double depth) {
    double size = depth - reached_;
    int halvings = 0;
    while (reached_ < depth) {
      const double target = std::min(depth, reached_ + size);
      if (balance_at(target)) {
        reached_ = target;
        equilibrium_ = state_.x;
      } else if (halvings++ < kMaxHalvings) {
        size *= 0.5;
        state_.x = equilibrium_;
      } else {
        throw std::runtime_error(fmt::format("the static solve at depth {:.4g} m does not converge ({}, {})", target,
                                             e_.model_name(), why_));
      }
    }
    return indenter_force();
  }

 private:
  Vec3 node_rest(std::int32_t n) const { return rest_.segment<3>(3 * n); }

  void apply_contact_set() {
    body_.fixed_dofs = support_;
    const bool punch = !e_.indenter.round();
    for (std::size_t k = 0; k < top_.size(); ++k) {
      if (!in_contact_[k]) continue;
      const auto i = 3 * static_cast<std::size_t>(top_[k]);
      body_.fixed_dofs[i + 2] = 1;
      if (punch) body_.fixed_dofs[i] = body_.fixed_dofs[i + 1] = 1;
    }
    physics::fixed_dofs_changed(body_, state_);
  }

  /// The sphere's lower surface above (x, y) at the current depth; +inf outside its radius.
  double sphere_z(double depth, double x, double y) const {
    const double r = e_.indenter.radius;
    const double rho2 = (x - top_centre_.x()) * (x - top_centre_.x()) + (y - top_centre_.y()) * (y - top_centre_.y());
    if (rho2 >= r * r) return std::numeric_limits<double>::infinity();
    return top_centre_.z() - depth + r - std::sqrt(r * r - rho2);
  }

  /// Places the held contact nodes for `depth` and balances; the sphere iterates its
  /// active set. False when a solve fails.
  bool balance_at(double depth) {
    const bool punch = !e_.indenter.round();
    for (int pass = 0; pass < (punch ? 1 : kMaxActiveSetPasses); ++pass) {
      if (!punch) {
        // Nodes now inside the sphere join the contact.
        bool added = false;
        for (std::size_t k = 0; k < top_.size(); ++k) {
          const Vec3 p = state_.x.segment<3>(3 * top_[k]);
          if (!in_contact_[k] && p.z() > sphere_z(depth, p.x(), p.y())) {
            in_contact_[k] = 1;
            added = true;
          }
        }
        if (added || pass == 0) apply_contact_set();
      }
      const VecX previous = state_.x;
      for (std::size_t k = 0; k < top_.size(); ++k) {
        if (!in_contact_[k]) continue;
        const auto i = 3 * static_cast<Eigen::Index>(top_[k]);
        if (punch) {
          state_.x.segment<3>(i) = rest_.segment<3>(i) - Vec3(0, 0, depth);
        } else {
          state_.x[i + 2] = sphere_z(depth, state_.x[i], state_.x[i + 1]);
          if (!std::isfinite(state_.x[i + 2])) state_.x[i + 2] = previous[i + 2];
        }
      }
      physics::StaticResult r;
      try {
        physics::predict_static(body_, state_, pass == 0 ? equilibrium_ : previous);
        r = physics::solve_static(body_, state_, {}, physics::StaticSettings{100, kNewtonTolerance, 1e-12});
      } catch (const std::runtime_error& err) {
        why_ = err.what();
        return false;
      }
      if (!r.converged || !state_.x.allFinite()) {
        why_ = r.inverted ? "an element turned inside out"
                          : fmt::format("out-of-balance force {:.3g} of the loads", r.residual);
        return false;
      }
      if (punch) return true;
      // Release nodes the body pulls into the sphere; re-project the held ones that slid.
      forces_.resize(state_.x.size());
      body_.model->forces(state_.x, state_.v, state_.q, forces_, *state_.model_scratch);
      bool changed = false;
      // A held node off the sphere by 1e-6 of the depth changes the force by about as much.
      const double tolerance = 1e-6 * depth;
      for (std::size_t k = 0; k < top_.size(); ++k) {
        const Vec3 p = state_.x.segment<3>(3 * top_[k]);
        const double surface = sphere_z(depth, p.x(), p.y());
        if (in_contact_[k] && forces_[3 * top_[k] + 2] < 0.0) {
          in_contact_[k] = 0;
          changed = true;
        } else if (in_contact_[k] && std::abs(p.z() - surface) > tolerance) {
          changed = true;
        } else if (!in_contact_[k] && p.z() > surface + tolerance) {
          changed = true;
        }
      }
      if (!changed) return true;
      apply_contact_set();
    }
    return true;  // the set still flickers at its rim: the last balanced state stands
  }

  /// Σ over the contact nodes of the body's force along +z: what the indenter feels.
  double indenter_force() {
    forces_.resize(state_.x.size());
    body_.model->forces(state_.x, state_.v, state_.q, forces_, *state_.model_scratch);
    double f = 0.0;
    for (std::size_t k = 0; k < top_.size(); ++k)
      if (in_contact_[k]) f += forces_[3 * top_[k] + 2];
    return f;
  }

  const Experiment& e_;
  Vec3 top_centre_;
  const std::vector<std::int32_t>& top_;
  physics::Body body_;
  physics::BodyState state_;
  std::vector<std::uint8_t> support_;
  std::vector<char> in_contact_;
  VecX rest_, equilibrium_, forces_;
  double reached_ = 0.0;
  std::string why_;
};

}  // namespace

IndentationModel::IndentationModel(const Experiment& experiment) : experiment_(&experiment) {
  const Specimen& s = experiment.specimen;
  if (s.mesh.empty()) {
    mesh_ = mesh::box_volume(Vec3(s.size.x(), s.size.y(), s.thickness), s.cells[0], s.cells[1], s.cells[2]);
    if (s.refine > 1.0) {
      // u in [−1, 1] → u (c + (1 − c) u²): slope c at the centre, 3 − 2c at the edges.
      const double c = 1.0 / s.refine;
      auto grade = [c](double u) { return u * (c + (1.0 - c) * u * u); };
      for (Vec3& v : mesh_.vertices) {
        v.x() = 0.5 * s.size.x() * grade(v.x() / (0.5 * s.size.x()));
        v.y() = 0.5 * s.size.y() * grade(v.y() / (0.5 * s.size.y()));
        // From the top face (t = 0) down to the bottom (t = 1), dense at the top.
        const double t = (0.5 * s.thickness - v.z()) / s.thickness;
        v.z() = 0.5 * s.thickness - s.thickness * grade(t);
      }
    }
  } else {
    mesh::MeshFile file = mesh::read_mesh(s.mesh);
    if (!file.volume || file.volume->tets.empty())
      throw InputError(SourceLocation{s.mesh.string(), {}, {}, {}}, "holds no tetrahedra (the specimen needs a volume mesh)");
    mesh_ = std::move(*file.volume);
  }
  double z_lo = std::numeric_limits<double>::infinity(), z_hi = -z_lo;
  Vec3 lo = Vec3::Constant(z_lo), hi = Vec3::Constant(z_hi);
  for (const Vec3& v : mesh_.vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  z_lo = lo.z();
  z_hi = hi.z();
  const double tolerance = 1e-6 * (hi - lo).norm();
  for (std::size_t i = 0; i < mesh_.vertices.size(); ++i) {
    if (mesh_.vertices[i].z() > z_hi - tolerance) top_nodes_.push_back(static_cast<std::int32_t>(i));
    if (mesh_.vertices[i].z() < z_lo + tolerance) bottom_nodes_.push_back(static_cast<std::int32_t>(i));
  }
  top_centre_ = Vec3(0.5 * (lo.x() + hi.x()), 0.5 * (lo.y() + hi.y()), z_hi);
  const std::string where = s.mesh.empty() ? experiment.file.string() : s.mesh.string();
  const double reach = experiment.indenter.radius;
  if (2 * reach >= std::min(hi.x() - lo.x(), hi.y() - lo.y()))
    throw InputError(SourceLocation{where, {}, {}, {}},
                     fmt::format("the indenter's diameter {:.4g} m is not smaller than the specimen's top face", 2 * reach));
  if (!experiment.indenter.round()) {
    const auto covered = std::count_if(top_nodes_.begin(), top_nodes_.end(), [&](std::int32_t n) {
      return horizontal_distance(mesh_.vertices[static_cast<std::size_t>(n)], top_centre_) <= reach * (1 + 1e-9);
    });
    if (covered == 0)
      throw InputError(SourceLocation{where, {}, {}, {}},
                       fmt::format("the flat punch of radius {:.4g} m covers no node of the top face; refine the mesh", reach));
  }
}

std::vector<double> IndentationModel::forces(const physics::FemMaterial& material, std::span<const double> depths) const {
  Press press(*this, *experiment_, top_centre_, top_nodes_, bottom_nodes_, material);
  std::vector<double> out;
  out.reserve(depths.size());
  for (double d : depths) out.push_back(d > 0.0 ? press.press_to(d) : 0.0);
  return out;
}

double IndentationModel::hold_depth(double t) const {
  const Hold& h = experiment_->hold;
  if (h.ramp_time <= 0.0 || t >= h.ramp_time) return h.value;
  return h.value * std::max(t, 0.0) / h.ramp_time;
}

std::vector<double> IndentationModel::curve(const physics::FemMaterial& material) const {
  const Experiment& e = *experiment_;
  if (e.kind == CurveKind::depth_force) {
    if (e.indenter.shape == IndenterShape::finger) return finger_forces(material);
    if (e.indenter.shape == IndenterShape::fingerpad) return fingerpad_forces(material);
    return forces(material, e.x);
  }
  if (e.kind == CurveKind::time_depth) return creep(material);
  // Relaxation: the elastic force along the ramp, relaxed by the hereditary integral.
  std::vector<double> times, depths;
  const int steps = e.hold.ramp_time > 0.0 ? kRampSteps : 1;
  for (int k = 1; k <= steps; ++k) {
    times.push_back(e.hold.ramp_time * k / steps);
    depths.push_back(e.hold.value * k / steps);
  }
  const std::vector<double> elastic = forces(material, depths);
  return hereditary_relaxation(material.prony, times, elastic, e.x);
}

std::vector<double> IndentationModel::finger_forces(const physics::FemMaterial& material) const {
  // Two elastic bodies in Hertz contact act as a rigid sphere on one body of compliance
  // c = (1 − ν₁²)/E₁ + (1 − ν₂²)/E₂ (Johnson, Contact Mechanics, eq. 4.22): at the same
  // approach the force is the rigid sphere's times c_tissue / (c_tissue + c_finger). Exact
  // on a half-space with the tissue's small-strain E and ν; on a layer or at large strain,
  // the finger's share is taken the same way.
  const double tissue = contact::contact_compliance({material.young_modulus, material.poisson_ratio});
  const double finger = contact::contact_compliance(experiment_->indenter.finger);
  std::vector<double> out = forces(material, experiment_->x);
  for (double& f : out) f *= tissue / (tissue + finger);
  return out;
}

std::vector<double> IndentationModel::fingerpad_forces(const physics::FemMaterial& material) const {
  // The pad in series with the tissue: the finger's depth D = d + the pad's compression at
  // F = F_tissue(d) (contact::FingerpadLaw::depth). F_tissue is pressed at the curve's depths, between them and below the
  // first (d < D always), and interpolated as a power law between those; D(d) increases,
  // so each depth's d is found by bisection.
  const contact::FingerpadLaw pad(experiment_->indenter.pad);
  const std::vector<double>& depths = experiment_->x;
  std::vector<double> pressed{depths.front() / 8.0, depths.front() / 4.0, depths.front() / 2.0};
  for (std::size_t k = 0; k < depths.size(); ++k) {
    pressed.push_back(depths[k]);
    if (k + 1 < depths.size()) pressed.push_back(std::sqrt(depths[k] * depths[k + 1]));
  }
  const std::vector<double> tissue = forces(material, pressed);
  if (!(tissue.front() > 0.0)) throw std::runtime_error("the specimen bears no force at an eighth of the first depth");
  auto force_at = [&](double d) { return power_law_between(pressed, tissue, d); };
  auto finger_depth = [&](double d) { return d + pad.depth(force_at(d)); };
  std::vector<double> out;
  for (const double depth : depths) {
    double lo = 0.0, hi = depth;
    for (int k = 0; k < 100 && hi - lo > 1e-12 * depth; ++k) {
      const double mid = 0.5 * (lo + hi);
      (finger_depth(mid) < depth ? lo : hi) = mid;
    }
    out.push_back(force_at(0.5 * (lo + hi)));
  }
  return out;
}

std::vector<double> IndentationModel::creep(const physics::FemMaterial& material) const {
  const Experiment& e = *experiment_;
  double g_inf = 1.0;
  for (const auto& p : material.prony) g_inf -= p.weight;
  if (!(g_inf > 0.0)) throw std::runtime_error("the Prony terms relax the whole modulus: a held force creeps without end");
  // The elastic force the creep tends to, F / g_inf, and the elastic curve past it: one press
  // to a small depth gives the scale, the curve's power (1.5 for a sphere, 1 for a punch)
  // where it will reach, then kCreepDepths depths up to 1.1 times that, more if short.
  const double target = e.hold.value / g_inf;
  const double power = e.indenter.round() ? 1.5 : 1.0;
  Press press(*this, e, top_centre_, top_nodes_, bottom_nodes_, material);
  std::vector<double> depths{1e-3 * e.specimen.thickness};
  std::vector<double> elastic{press.press_to(depths[0])};
  if (!(elastic[0] > 0.0)) throw std::runtime_error("the specimen bears no force at a small depth");
  const double reach = depths[0] * std::pow(target / elastic[0], 1.0 / power);
  for (int k = 1; k <= kCreepDepths && elastic.back() < 1.05 * target; ++k) {
    const double d = std::max(depths.back() * 1.05, 1.1 * reach * k / kCreepDepths);
    depths.push_back(d);
    elastic.push_back(press.press_to(d));
  }
  for (int extra = 0; elastic.back() < 1.05 * target; ++extra) {
    if (extra == kCreepDepths)
      throw std::runtime_error(fmt::format("the specimen does not bear {:.4g} N (the creep's limit) within {:.4g} m",
                                           target, depths.back()));
    depths.push_back(depths.back() * 1.2);
    elastic.push_back(press.press_to(depths.back()));
  }
  const std::vector<double> phi = hereditary_creep(material.prony, e.hold.value, e.hold.ramp_time, e.x);
  // δ = F_e⁻¹(φ): power-law (log–log) interpolation between the pressed depths, the power of
  // the first two below the first.
  std::vector<double> out;
  out.reserve(phi.size());
  for (double f : phi) {
    if (f <= 0.0) {
      out.push_back(0.0);
      continue;
    }
    out.push_back(power_law_between(elastic, depths, f));
  }
  return out;
}

std::vector<double> hereditary_creep(const std::vector<physics::PronyTerm>& prony, double force, double ramp_time,
                                     std::span<const double> times) {
  double g_inf = 1.0;
  for (const auto& p : prony) g_inf -= p.weight;
  double tau_min = std::numeric_limits<double>::infinity();
  for (const auto& p : prony) tau_min = std::min(tau_min, p.tau);
  const double t_end = times.empty() ? 0.0 : *std::max_element(times.begin(), times.end());
  // The quadrature's times: the ramp in kCreepRampSteps, the hold in steps of a fiftieth of
  // the shortest τ (at most kCreepMaxSteps), and every asked time.
  std::vector<double> grid{0.0};
  if (ramp_time > 0.0)
    for (int k = 1; k <= kCreepRampSteps; ++k) grid.push_back(ramp_time * k / kCreepRampSteps);
  const double start = std::max(ramp_time, 0.0);
  if (t_end > start) {
    const double step = std::max(std::min(tau_min, t_end) / 50.0, (t_end - start) / kCreepMaxSteps);
    for (double t = start + step; t < t_end; t += step) grid.push_back(t);
  }
  for (double t : times) grid.push_back(std::max(t, 0.0));
  std::sort(grid.begin(), grid.end());
  grid.erase(std::unique(grid.begin(), grid.end()), grid.end());
  auto load = [&](double t) { return ramp_time > 0.0 && t < ramp_time ? force * t / ramp_time : force; };

  // F(t_n) = g_inf φ_n + Σ_i g_i S_i(n), S_i(n) = Σ_k exp(−(t_n − m_k)/τ_i) Δφ_k with m_k the
  // midpoint of step k (the relaxation's quadrature): S_i follows step by step, so each Δφ_n
  // solves one equation.
  std::vector<double> sum(prony.size(), 0.0);
  std::vector<double> phi(grid.size(), 0.0);
  double previous = 0.0, t_previous = 0.0;
  for (std::size_t n = 0; n < grid.size(); ++n) {
    const double dt = grid[n] - t_previous;
    double rest = load(grid[n]) - g_inf * previous, weight = g_inf;
    for (std::size_t i = 0; i < prony.size(); ++i) {
      sum[i] *= std::exp(-dt / prony[i].tau);
      rest -= prony[i].weight * sum[i];
      weight += prony[i].weight * std::exp(-0.5 * dt / prony[i].tau);
    }
    const double increment = rest / weight;
    for (std::size_t i = 0; i < prony.size(); ++i) sum[i] += std::exp(-0.5 * dt / prony[i].tau) * increment;
    previous += increment;
    phi[n] = previous;
    t_previous = grid[n];
  }
  std::vector<double> out;
  out.reserve(times.size());
  for (double t : times) out.push_back(phi[static_cast<std::size_t>(std::lower_bound(grid.begin(), grid.end(), std::max(t, 0.0)) - grid.begin())]);
  return out;
}

std::vector<double> hereditary_relaxation(const std::vector<physics::PronyTerm>& prony, std::span<const double> ramp_times,
                                          std::span<const double> ramp_forces, std::span<const double> times) {
  double g_inf = 1.0;
  for (const auto& p : prony) g_inf -= p.weight;
  auto modulus = [&](double s) {
    double g = g_inf;
    for (const auto& p : prony) g += p.weight * std::exp(-s / p.tau);
    return g;
  };
  std::vector<double> out;
  out.reserve(times.size());
  for (double t : times) {
    // Each ramp step adds its force increment at its midpoint; a step the time t is inside
    // adds the part of it loaded so far (the force interpolated linearly within the step).
    double f = 0.0, t0 = 0.0, f0 = 0.0;
    for (std::size_t k = 0; k < ramp_times.size(); ++k) {
      const double t1 = ramp_times[k], f1 = ramp_forces[k];
      if (t1 <= t0) {  // a step load at t0
        if (t >= t0) f += modulus(t - t0) * (f1 - f0);
      } else if (t > t0) {
        const double end = std::min(t, t1);
        const double df = (f1 - f0) * (end - t0) / (t1 - t0);
        f += modulus(t - 0.5 * (t0 + end)) * df;
      }
      t0 = t1;
      f0 = f1;
    }
    out.push_back(f);
  }
  return out;
}

}  // namespace tactus::fitting
