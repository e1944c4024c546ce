#include "physics/fem/nodal_pressure.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "core/error.hpp"

namespace tactus::physics {
namespace {

using Corners = std::array<Vec3, 4>;

Corners corners_of(const VecX& x, const TetElement& el) {
  Corners c;
  for (std::size_t i = 0; i < 4; ++i) c[i] = x.segment<3>(3 * static_cast<Eigen::Index>(el.nodes[i]));
  return c;
}

/// sign·(x1 − x0)·((x2 − x0) × (x3 − x0))/6, the element's volume in the sign that makes it
/// positive at rest, and its gradient with respect to each corner.
double volume_and_gradient(const Corners& x, double sign, Corners& grad) {
  const Vec3 e1 = x[1] - x[0], e2 = x[2] - x[0], e3 = x[3] - x[0];
  const double k = sign / 6.0;
  grad[1] = k * e2.cross(e3);
  grad[2] = k * e3.cross(e1);
  grad[3] = k * e1.cross(e2);
  grad[0] = -(grad[1] + grad[2] + grad[3]);
  return k * e1.dot(e2.cross(e3));
}

/// The change of the volume gradient when the corners move by dx: (∂²v/∂x²)·dx.
Corners gradient_change(const Corners& x, double sign, const Corners& dx) {
  const Vec3 e1 = x[1] - x[0], e2 = x[2] - x[0], e3 = x[3] - x[0];
  const Vec3 d1 = dx[1] - dx[0], d2 = dx[2] - dx[0], d3 = dx[3] - dx[0];
  const double k = sign / 6.0;
  Corners g;
  g[1] = k * (d2.cross(e3) + e2.cross(d3));
  g[2] = k * (d3.cross(e1) + e3.cross(d1));
  g[3] = k * (d1.cross(e2) + e1.cross(d2));
  g[0] = -(g[1] + g[2] + g[3]);
  return g;
}

Eigen::Index dof(std::int32_t node) { return 3 * static_cast<Eigen::Index>(node); }

}  // namespace

/// The volumetric term at one configuration.
struct NodalPressureFem::State {
  VecX x;                             ///< where it was evaluated
  std::vector<Corners> gradient;      ///< ∂v_e/∂x per element corner
  VecX pressure;                      ///< p_a per node
  std::vector<double> mean_pressure;  ///< p̄_e per element
};

struct NodalPressureFem::Work final : Scratch {
  std::unique_ptr<Scratch> inner;
  State linearized, evaluated;
  bool exact = false;
  mutable VecX node_sum;  ///< the products' per-node sums
};

NodalPressureFem::NodalPressureFem(std::shared_ptr<const TetFem> isochoric) : inner_(std::move(isochoric)) {
  if (!inner_) throw InputError("nodal pressure: no FEM body");
  for (const FemMaterial& m : inner_->materials())
    if (!m.nodal_pressure)
      throw InputError("nodal pressure: every material of the FEM body must set nodal_pressure (its elements then "
                       "leave out the volumetric term this model adds)");
  const auto nodes = static_cast<Eigen::Index>(inner_->node_count());
  rest_volume_ = VecX::Zero(nodes);
  kappa_ = VecX::Zero(nodes);
  node_elements_.assign(static_cast<std::size_t>(nodes), {});
  const auto& elements = inner_->elements();
  sign_.resize(elements.size());
  for (std::size_t e = 0; e < elements.size(); ++e) {
    const TetElement& el = elements[e];
    Corners g;
    sign_[e] = volume_and_gradient(corners_of(inner_->rest_positions(), el), 1.0, g) < 0.0 ? -1.0 : 1.0;
    const double kappa = LawParams::from(inner_->materials()[static_cast<std::size_t>(el.material)]).kappa;
    for (const std::int32_t n : el.nodes) {
      rest_volume_[n] += el.volume / 4.0;
      kappa_[n] += kappa * el.volume / 4.0;
      node_elements_[static_cast<std::size_t>(n)].push_back(static_cast<std::int32_t>(e));
    }
  }
  for (Eigen::Index n = 0; n < nodes; ++n)
    if (rest_volume_[n] > 0.0) kappa_[n] /= rest_volume_[n];
}

std::unique_ptr<Scratch> NodalPressureFem::make_scratch() const {
  auto w = std::make_unique<Work>();
  w->inner = inner_->make_scratch();
  return w;
}

void NodalPressureFem::evaluate(const VecX& x, State& s) const {
  const auto& elements = inner_->elements();
  s.x = x;
  s.gradient.resize(elements.size());
  s.mean_pressure.resize(elements.size());
  s.pressure.setZero(rest_volume_.size());
  VecX& p = s.pressure;  // the nodal volumes v_a first, then p_a in place
  for (std::size_t e = 0; e < elements.size(); ++e) {
    const double v = volume_and_gradient(corners_of(x, elements[e]), sign_[e], s.gradient[e]);
    for (const std::int32_t n : elements[e].nodes) p[n] += v / 4.0;
  }
  for (Eigen::Index n = 0; n < p.size(); ++n)
    p[n] = rest_volume_[n] > 0.0 ? kappa_[n] * (p[n] / rest_volume_[n] - 1.0) : 0.0;
  for (std::size_t e = 0; e < elements.size(); ++e) {
    double sum = 0.0;
    for (const std::int32_t n : elements[e].nodes) sum += p[n];
    s.mean_pressure[e] = sum / 4.0;
  }
}

VecX NodalPressureFem::nodal_pressures(const VecX& x) const {
  State s;
  evaluate(x, s);
  return s.pressure;
}

void NodalPressureFem::forces(const VecX& x, const VecX& v, const VecX& q, VecX& f, Scratch& scratch) const {
  auto& w = static_cast<Work&>(scratch);
  inner_->forces(x, v, q, f, *w.inner);
  evaluate(x, w.evaluated);
  const auto& elements = inner_->elements();
  for (std::size_t e = 0; e < elements.size(); ++e)
    for (std::size_t i = 0; i < 4; ++i)
      f.segment<3>(dof(elements[e].nodes[i])) -= w.evaluated.mean_pressure[e] * w.evaluated.gradient[e][i];
}

void NodalPressureFem::linearize(const VecX& x, const VecX& v, const VecX& q, Scratch& scratch) const {
  auto& w = static_cast<Work&>(scratch);
  inner_->linearize(x, v, q, *w.inner);
  evaluate(x, w.linearized);
  w.exact = false;
}

bool NodalPressureFem::linearize_exact(const VecX& x, const VecX& v, const VecX& q, Scratch& scratch) const {
  auto& w = static_cast<Work&>(scratch);
  if (!inner_->linearize_exact(x, v, q, *w.inner)) inner_->linearize(x, v, q, *w.inner);
  evaluate(x, w.linearized);
  w.exact = true;
  return true;
}

void NodalPressureFem::add_volumetric_product(const VecX& dx, VecX& out, const Work& w) const {
  // Σ_a κ_a/V_a g_a (g_a·dx): per element s_e = ∇v_e·dx, per node t_a = Σ_{e∋a} s_e/4 = g_a·dx,
  // scaled to c_a = κ_a/V_a t_a, and back through each element's mean of its nodes' c.
  const State& s = w.linearized;
  const auto& elements = inner_->elements();
  VecX& c = w.node_sum;
  c.setZero(rest_volume_.size());
  for (std::size_t e = 0; e < elements.size(); ++e) {
    double se = 0.0;
    for (std::size_t i = 0; i < 4; ++i) se += s.gradient[e][i].dot(dx.segment<3>(dof(elements[e].nodes[i])));
    for (const std::int32_t n : elements[e].nodes) c[n] += se / 4.0;
  }
  for (Eigen::Index n = 0; n < c.size(); ++n) c[n] = rest_volume_[n] > 0.0 ? kappa_[n] / rest_volume_[n] * c[n] : 0.0;
  for (std::size_t e = 0; e < elements.size(); ++e) {
    double mean = 0.0;
    for (const std::int32_t n : elements[e].nodes) mean += c[n];
    mean /= 4.0;
    Corners change;
    for (Vec3& v : change) v.setZero();
    if (w.exact) {
      Corners d;
      for (std::size_t i = 0; i < 4; ++i) d[i] = dx.segment<3>(dof(elements[e].nodes[i]));
      change = gradient_change(corners_of(s.x, elements[e]), sign_[e], d);
    }
    for (std::size_t i = 0; i < 4; ++i) {
      Vec3 add = mean * s.gradient[e][i];
      if (w.exact) add += s.mean_pressure[e] * change[i];  // the geometric part, Σ_e p̄_e ∂²v_e/∂x²·dx
      out.segment<3>(dof(elements[e].nodes[i])) += add;
    }
  }
}

void NodalPressureFem::add_stiffness_product(const VecX& dx, VecX& out, const Scratch& scratch) const {
  const auto& w = static_cast<const Work&>(scratch);
  inner_->add_stiffness_product(dx, out, *w.inner);
  add_volumetric_product(dx, out, w);
}

void NodalPressureFem::add_damping_product(const VecX& dv, VecX& out, const Scratch& scratch) const {
  inner_->add_damping_product(dv, out, *static_cast<const Work&>(scratch).inner);
}

void NodalPressureFem::add_system_product(double a, double b, double c, const VecX& in, VecX& out,
                                          const Scratch& scratch) const {
  const auto& w = static_cast<const Work&>(scratch);
  inner_->add_system_product(a, b, c, in, out, *w.inner);
  if (c == 0.0) return;
  thread_local VecX scaled;
  scaled = c * in;
  add_volumetric_product(scaled, out, w);
}

/// g_a's entries, ∂v_a/∂x_j = Σ_{e∋a, e∋j} ∇_j v_e / 4, node by node.
std::vector<std::pair<std::int32_t, Vec3>> NodalPressureFem::nodal_gradient(std::int32_t a, const State& s) const {
  std::vector<std::pair<std::int32_t, Vec3>> g;
  const auto& elements = inner_->elements();
  for (const std::int32_t e : node_elements_[static_cast<std::size_t>(a)])
    for (std::size_t i = 0; i < 4; ++i) {
      const std::int32_t j = elements[static_cast<std::size_t>(e)].nodes[i];
      auto it = std::find_if(g.begin(), g.end(), [&](const auto& entry) { return entry.first == j; });
      if (it == g.end()) it = g.insert(g.end(), {j, Vec3::Zero()});
      it->second += s.gradient[static_cast<std::size_t>(e)][i] / 4.0;
    }
  return g;
}

template <class Visit>
void NodalPressureFem::for_each_node_term(double a, const State& s, Visit&& visit) const {
  for (Eigen::Index n = 0; n < rest_volume_.size(); ++n)
    if (rest_volume_[n] > 0.0) visit(a * kappa_[n] / rest_volume_[n], nodal_gradient(static_cast<std::int32_t>(n), s));
}

void NodalPressureFem::add_diagonal(double a, double b, VecX& out, const Scratch& scratch) const {
  const auto& w = static_cast<const Work&>(scratch);
  inner_->add_diagonal(a, b, out, *w.inner);
  if (a == 0.0) return;
  // The geometric part's diagonal blocks are zero (v_e is linear in each corner alone).
  for_each_node_term(a, w.linearized, [&](double k, const auto& g) {
    for (const auto& [j, gj] : g) out.segment<3>(dof(j)) += k * gj.cwiseAbs2();
  });
}

void NodalPressureFem::add_triplets(double a, double b, std::vector<Triplet>& out, const Scratch& scratch) const {
  const auto& w = static_cast<const Work&>(scratch);
  inner_->add_triplets(a, b, out, *w.inner);
  if (a == 0.0) return;
  for_each_node_term(a, w.linearized, [&](double k, const auto& g) {
    for (const auto& [i, gi] : g)
      for (const auto& [j, gj] : g) {
        const Mat3 block = k * gi * gj.transpose();
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 3; ++c) out.emplace_back(dof(i) + r, dof(j) + c, block(r, c));
      }
  });
  if (!w.exact) return;
  // Σ_e p̄_e ∂²v_e/∂x², column by column from the gradient's change along each corner's axes.
  const auto& elements = inner_->elements();
  for (std::size_t e = 0; e < elements.size(); ++e) {
    const Corners x = corners_of(w.linearized.x, elements[e]);
    const double p = a * w.linearized.mean_pressure[e];
    for (std::size_t j = 0; j < 4; ++j)
      for (int c = 0; c < 3; ++c) {
        Corners d;
        for (Vec3& v : d) v.setZero();
        d[j][c] = 1.0;
        const Corners column = gradient_change(x, sign_[e], d);
        for (std::size_t i = 0; i < 4; ++i) {
          if (i == j) continue;  // zero
          for (int r = 0; r < 3; ++r)
            out.emplace_back(dof(elements[e].nodes[i]) + r, dof(elements[e].nodes[j]) + c, p * column[i][r]);
        }
      }
  }
}

void NodalPressureFem::update_internal(const VecX& x, double dt, VecX& q, Scratch& scratch) const {
  inner_->update_internal(x, dt, q, *static_cast<Work&>(scratch).inner);
}

double NodalPressureFem::elastic_energy(const VecX& x, const VecX& q) const {
  State s;
  evaluate(x, s);
  double u = 0.0;
  for (Eigen::Index n = 0; n < s.pressure.size(); ++n)
    if (kappa_[n] > 0.0) u += rest_volume_[n] * s.pressure[n] * s.pressure[n] / (2.0 * kappa_[n]);
  return inner_->elastic_energy(x, q) + u;
}

const TetFem* tet_fem_of(const ForceModel* model) {
  if (const auto* fem = dynamic_cast<const TetFem*>(model)) return fem;
  if (const auto* nodal = dynamic_cast<const NodalPressureFem*>(model)) return &nodal->isochoric();
  return nullptr;
}

}  // namespace tactus::physics
