#include "physics/mass_spring/spring_network.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <string>

#include "core/error.hpp"

namespace tactus::physics {
namespace {

/// Linearization of one state: per spring its stiffness block H (K_ii = K_jj = H,
/// K_ij = −H) and direction; per angle its Hessian in (u, w).
struct NetworkScratch final : Scratch {
  std::vector<Mat3> spring_k;
  std::vector<Vec3> dir;
  std::vector<Mat6> angle_k;
  double decay_dt = -1.0;     // the step the arm decay factors below were computed for
  std::vector<double> decay;  // e^(−dt k/c) per arm
};

inline auto node(const VecX& x, std::int32_t n) { return x.segment<3>(3 * static_cast<Eigen::Index>(n)); }
inline auto node(VecX& x, std::int32_t n) { return x.segment<3>(3 * static_cast<Eigen::Index>(n)); }

// Which edge vectors a node of an angle term moves: u = x_a − x_b, w = x_c − x_b.
constexpr double kCoefU[3] = {1.0, -1.0, 0.0};
constexpr double kCoefW[3] = {0.0, -1.0, 1.0};

/// Block (p, q) of Sᵀ H S, S mapping node displacements (a, b, c) to (u, w).
Mat3 angle_block(const Mat6& h, int p, int q) {
  return kCoefU[p] * kCoefU[q] * h.topLeftCorner<3, 3>() + kCoefU[p] * kCoefW[q] * h.topRightCorner<3, 3>() +
         kCoefW[p] * kCoefU[q] * h.bottomLeftCorner<3, 3>() + kCoefW[p] * kCoefW[q] * h.bottomRightCorner<3, 3>();
}

}  // namespace

SpringNetwork::SpringNetwork(VecX rest, const VecX& node_mass, SpringNetworkOptions options)
    : rest_(std::move(rest)), options_(options) {
  if (rest_.size() % 3 != 0 || node_mass.size() * 3 != rest_.size())
    throw InputError("spring network: need 3 coordinates and one mass per node");
  if (!rest_.allFinite()) throw InputError("spring network: rest positions must be finite");
  mass_.resize(rest_.size());
  for (Eigen::Index n = 0; n < node_mass.size(); ++n) {
    if (!(node_mass[n] > 0.0 && std::isfinite(node_mass[n])))
      throw InputError("spring network: node " + std::to_string(n) + " needs a positive mass");
    mass_.segment<3>(3 * n).setConstant(node_mass[n]);
  }
  damping_ = VecX::Zero(rest_.size());
}

void SpringNetwork::check_node(std::int32_t n) const {
  if (n < 0 || static_cast<std::size_t>(n) >= node_count())
    throw InputError("spring network: node " + std::to_string(n) + " out of range");
}

std::int32_t SpringNetwork::add_spring(std::int32_t i, std::int32_t j, double stiffness, double damping,
                                       const std::vector<SpringArm>& arms) {
  check_node(i);
  check_node(j);
  if (i == j) throw InputError("spring network: a spring needs two different nodes");
  if (!(stiffness >= 0.0 && damping >= 0.0 && std::isfinite(stiffness) && std::isfinite(damping)))
    throw InputError("spring network: stiffness and damping must be finite and >= 0");
  Spring s;
  s.i = i;
  s.j = j;
  s.stiffness = stiffness;
  s.damping = damping;
  s.rest_length = (node(rest_, j) - node(rest_, i)).norm();
  if (!(s.rest_length > 0.0)) throw InputError("spring network: spring between coincident nodes");
  s.arm_begin = static_cast<std::int32_t>(arms_.size());
  s.arm_count = static_cast<std::int32_t>(arms.size());
  for (const auto& a : arms) {
    if (!(a.stiffness >= 0.0 && a.damping > 0.0 && std::isfinite(a.stiffness) && std::isfinite(a.damping)))
      throw InputError("spring network: an arm needs stiffness >= 0 and damping > 0");
    arms_.push_back(a);
  }
  springs_.push_back(s);
  return static_cast<std::int32_t>(springs_.size() - 1);
}

void SpringNetwork::add_angle(std::int32_t a, std::int32_t b, std::int32_t c, double stiffness) {
  check_node(a);
  check_node(b);
  check_node(c);
  if (!(stiffness >= 0.0 && std::isfinite(stiffness)))
    throw InputError("spring network: angle stiffness must be finite and >= 0");
  AngleSpring t{a, b, c, stiffness, angle_between(node(rest_, a) - node(rest_, b), node(rest_, c) - node(rest_, b))};
  angles_.push_back(t);
}

void SpringNetwork::set_nodal_damping(std::int32_t n, double d) {
  check_node(n);
  if (!(d >= 0.0 && std::isfinite(d))) throw InputError("spring network: nodal damping must be >= 0");
  node(damping_, n).setConstant(d);
}

std::shared_ptr<SpringNetwork> SpringNetwork::restricted(const std::vector<std::uint8_t>& node_fixed) const {
  if (node_fixed.size() != node_count()) throw InputError("spring network: one fixed flag per node expected");
  auto out = std::make_shared<SpringNetwork>(*this);
  out->springs_.clear();
  out->angles_.clear();
  const auto fixed = [&](std::int32_t n) { return node_fixed[static_cast<std::size_t>(n)] != 0; };
  for (const auto& s : springs_)
    if (!fixed(s.i) || !fixed(s.j)) out->springs_.push_back(s);
  for (const auto& t : angles_)
    if (!fixed(t.a) || !fixed(t.b) || !fixed(t.c)) out->angles_.push_back(t);
  return out;
}

std::unique_ptr<Scratch> SpringNetwork::make_scratch() const {
  auto s = std::make_unique<NetworkScratch>();
  s->spring_k.resize(springs_.size());
  s->dir.resize(springs_.size());
  s->angle_k.resize(angles_.size());
  s->decay.resize(arms_.size());
  return s;
}

void SpringNetwork::forces(const VecX& x, const VecX& v, const VecX& q, VecX& f, Scratch&) const {
  // Nodal absolute damping −d_i u̇_i (seed 000 eq. 9, seed 004's −k_d v_i).
  f = -damping_.cwiseProduct(v);
  for (const Spring& s : springs_) {
    const Vec3 d = node(x, s.j) - node(x, s.i);
    const double l = d.norm();
    if (!(l > 0.0)) continue;  // coincident nodes: no direction to push along
    const Vec3 n = d / l;
    const double e = l - s.rest_length;
    double t = s.stiffness * e;  // tension: Hooke (seed 000 eq. 9)
    for (std::int32_t k = 0; k < s.arm_count; ++k) {
      const SpringArm& arm = arms_[static_cast<std::size_t>(s.arm_begin + k)];
      t += arm.stiffness * (e - q[s.arm_begin + k]);  // arm spring stretch = e − dashpot elongation
    }
    if (s.damping != 0.0) t += s.damping * n.dot(node(v, s.j) - node(v, s.i));
    node(f, s.i) += t * n;
    node(f, s.j) -= t * n;
  }
  for (const AngleSpring& a : angles_) {
    const Vec3 xb = node(x, a.b);
    const AngleDerivatives ad = angle_derivatives(node(x, a.a) - xb, node(x, a.c) - xb, false);
    if (!ad.valid) continue;
    const double m = -a.stiffness * (ad.theta - a.rest_angle);  // −dE/dθ
    const Vec3 fu = m * ad.grad.head<3>(), fw = m * ad.grad.tail<3>();
    node(f, a.a) += fu;
    node(f, a.c) += fw;
    node(f, a.b) -= fu + fw;
  }
}

void SpringNetwork::linearize(const VecX& x, const VecX&, const VecX& q, Scratch& scratch) const {
  auto& s = static_cast<NetworkScratch&>(scratch);
  for (std::size_t k = 0; k < springs_.size(); ++k) {
    const Spring& sp = springs_[k];
    const Vec3 d = node(x, sp.j) - node(x, sp.i);
    const double l = d.norm();
    if (!(l > 0.0)) {
      s.spring_k[k].setZero();
      s.dir[k].setZero();
      continue;
    }
    const Vec3 n = d / l;
    const double e = l - sp.rest_length;
    double ka = sp.stiffness, t = sp.stiffness * e;
    for (std::int32_t a = 0; a < sp.arm_count; ++a) {
      const SpringArm& arm = arms_[static_cast<std::size_t>(sp.arm_begin + a)];
      ka += arm.stiffness;
      t += arm.stiffness * (e - q[sp.arm_begin + a]);
    }
    // Hessian of the elastic energy: axial k n nᵀ plus the transverse T/l (I − n nᵀ). The
    // dashpot's dependence on x through n is left out (it vanishes at rest and is not
    // symmetric).
    if (options_.project_compressed && t < 0.0) t = 0.0;
    const Mat3 nn = n * n.transpose();
    s.spring_k[k] = ka * nn + (t / l) * (Mat3::Identity() - nn);
    s.dir[k] = n;
  }
  for (std::size_t k = 0; k < angles_.size(); ++k) {
    const AngleSpring& a = angles_[k];
    const Vec3 xb = node(x, a.b);
    const bool full = options_.angle_hessian != AngleHessian::gauss_newton;
    const AngleDerivatives ad = angle_derivatives(node(x, a.a) - xb, node(x, a.c) - xb, full);
    Mat6& h = s.angle_k[k];
    if (!ad.valid) {
      h.setZero();
      continue;
    }
    h = a.stiffness * ad.grad * ad.grad.transpose();
    if (full) h += a.stiffness * (ad.theta - a.rest_angle) * ad.hess;
    if (options_.angle_hessian == AngleHessian::projected) {
      Eigen::SelfAdjointEigenSolver<Mat6> eig(h);
      h = eig.eigenvectors() * eig.eigenvalues().cwiseMax(0.0).asDiagonal() * eig.eigenvectors().transpose();
    }
  }
}

void SpringNetwork::add_stiffness_product(const VecX& dx, VecX& out, const Scratch& scratch) const {
  const auto& s = static_cast<const NetworkScratch&>(scratch);
  for (std::size_t k = 0; k < springs_.size(); ++k) {
    const Spring& sp = springs_[k];
    const Vec3 y = s.spring_k[k] * (node(dx, sp.j) - node(dx, sp.i));
    node(out, sp.i) -= y;
    node(out, sp.j) += y;
  }
  for (std::size_t k = 0; k < angles_.size(); ++k) {
    const AngleSpring& a = angles_[k];
    Vec6 z;
    z << node(dx, a.a) - node(dx, a.b), node(dx, a.c) - node(dx, a.b);
    const Vec6 y = s.angle_k[k] * z;
    node(out, a.a) += y.head<3>();
    node(out, a.c) += y.tail<3>();
    node(out, a.b) -= y.head<3>() + y.tail<3>();
  }
}

void SpringNetwork::add_damping_product(const VecX& dv, VecX& out, const Scratch& scratch) const {
  const auto& s = static_cast<const NetworkScratch&>(scratch);
  out += damping_.cwiseProduct(dv);
  for (std::size_t k = 0; k < springs_.size(); ++k) {
    const Spring& sp = springs_[k];
    if (sp.damping == 0.0) continue;
    const Vec3& n = s.dir[k];
    const Vec3 y = sp.damping * n.dot(node(dv, sp.j) - node(dv, sp.i)) * n;
    node(out, sp.i) -= y;
    node(out, sp.j) += y;
  }
}

void SpringNetwork::add_diagonal(double a, double b, VecX& out, const Scratch& scratch) const {
  const auto& s = static_cast<const NetworkScratch&>(scratch);
  out += b * damping_;
  for (std::size_t k = 0; k < springs_.size(); ++k) {
    const Spring& sp = springs_[k];
    const Vec3 d = a * s.spring_k[k].diagonal() + b * sp.damping * s.dir[k].cwiseAbs2();
    node(out, sp.i) += d;
    node(out, sp.j) += d;
  }
  for (std::size_t k = 0; k < angles_.size(); ++k) {
    const AngleSpring& t = angles_[k];
    const std::int32_t ids[3] = {t.a, t.b, t.c};
    for (int p = 0; p < 3; ++p) node(out, ids[p]) += a * angle_block(s.angle_k[k], p, p).diagonal();
  }
}

void SpringNetwork::add_triplets(double a, double b, std::vector<Triplet>& out, const Scratch& scratch) const {
  const auto& s = static_cast<const NetworkScratch&>(scratch);
  const auto block = [&out](std::int32_t p, std::int32_t q, const Mat3& m) {
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) out.emplace_back(3 * p + r, 3 * q + c, m(r, c));
  };
  if (b != 0.0)
    for (Eigen::Index i = 0; i < damping_.size(); ++i)
      if (damping_[i] != 0.0) out.emplace_back(i, i, b * damping_[i]);
  for (std::size_t k = 0; k < springs_.size(); ++k) {
    const Spring& sp = springs_[k];
    const Mat3 w = a * s.spring_k[k] + (b * sp.damping) * s.dir[k] * s.dir[k].transpose();
    block(sp.i, sp.i, w);
    block(sp.j, sp.j, w);
    block(sp.i, sp.j, -w);
    block(sp.j, sp.i, -w);
  }
  if (a == 0.0) return;
  for (std::size_t k = 0; k < angles_.size(); ++k) {
    const AngleSpring& t = angles_[k];
    const std::int32_t ids[3] = {t.a, t.b, t.c};
    for (int p = 0; p < 3; ++p)
      for (int q = 0; q < 3; ++q) block(ids[p], ids[q], a * angle_block(s.angle_k[k], p, q));
  }
}

void SpringNetwork::update_internal(const VecX& x, double dt, VecX& q, Scratch& scratch) const {
  auto& sc = static_cast<NetworkScratch&>(scratch);
  if (sc.decay_dt != dt) {  // steps are usually constant: one exp per arm per change of dt
    for (std::size_t k = 0; k < arms_.size(); ++k) sc.decay[k] = std::exp(-dt * arms_[k].stiffness / arms_[k].damping);
    sc.decay_dt = dt;
  }
  // Each arm's dashpot obeys c ẏ = k (e − y). With the spring elongation e held at its
  // end-of-step value, y(t + dt) = e + (y − e) e^(−dt k/c): exact, stable for any dt.
  for (const Spring& s : springs_) {
    if (s.arm_count == 0) continue;
    const double e = (node(x, s.j) - node(x, s.i)).norm() - s.rest_length;
    for (std::int32_t k = 0; k < s.arm_count; ++k) {
      double& y = q[s.arm_begin + k];
      y = e + (y - e) * sc.decay[static_cast<std::size_t>(s.arm_begin + k)];
    }
  }
}

double SpringNetwork::elastic_energy(const VecX& x, const VecX& q) const {
  double energy = 0.0;
  for (const Spring& s : springs_) {
    const double e = (node(x, s.j) - node(x, s.i)).norm() - s.rest_length;
    energy += 0.5 * s.stiffness * e * e;
    for (std::int32_t k = 0; k < s.arm_count; ++k) {
      const double stretch = e - q[s.arm_begin + k];
      energy += 0.5 * arms_[static_cast<std::size_t>(s.arm_begin + k)].stiffness * stretch * stretch;
    }
  }
  for (const AngleSpring& a : angles_) {
    const Vec3 xb = node(x, a.b);
    const double dth = angle_between(node(x, a.a) - xb, node(x, a.c) - xb) - a.rest_angle;
    energy += 0.5 * a.stiffness * dth * dth;
  }
  return energy;
}

}  // namespace tactus::physics
