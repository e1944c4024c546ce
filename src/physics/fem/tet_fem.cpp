#include "physics/fem/tet_fem.hpp"

#include <algorithm>
#include <cmath>
#include <span>
#include <string>

#include "core/error.hpp"
#include "core/parallel.hpp"
#include "physics/fem/polar.hpp"
#include "physics/fem/prony.hpp"

namespace tactus::physics {

/// Per-state caches: element rotations (keyed by the positions they were computed at, so a
/// force evaluation and a linearization at the same x share them) and tangents.
struct TetFem::Cache final : Scratch {
  std::vector<Mat3> rotation;
  /// sqrt(V) R G per element: with these, R K0 R^T is the linear kernel (see below).
  std::vector<Eigen::Matrix<double, 3, 4>> rotated_grad;
  VecX rotation_x;
  bool rotations_valid = false;
  std::vector<Mat9> tangent;  ///< hyperelastic: dP/dF per element (projected if asked)
  /// Each element's contribution to its four nodes (12 values per element), written by the
  /// element pass and summed per node by gather(); scratch space of const products.
  mutable std::vector<Vec3> columns;
};

namespace {

using Mat12 = Eigen::Matrix<double, 12, 12>;

// Loops shorter than two grains run on the calling thread: waking the pool's workers costs
// more than the work they share below about 8,000 tetrahedra on the 2-core machine
// (docs/BENCHMARKS.md).
constexpr std::size_t kElementGrain = 4096, kNodeGrain = 1024;

/// Small-strain stress of a displacement gradient M: lambda tr(M) I + mu (M + M^T).
inline Mat3 hooke_of_gradient(double lambda, double mu, const Mat3& M) {
  Mat3 s = mu * (M + M.transpose());
  s.diagonal().array() += lambda * M.trace();
  return s;
}

inline Mat3 gradient_of(const VecX& x, const TetElement& el) {
  Mat3 F = Mat3::Zero();
  for (int a = 0; a < 4; ++a) F.noalias() += x.segment<3>(3 * el.nodes[a]) * el.grad.col(a).transpose();
  return F;
}

inline Mat3 deviator(const Mat3& m) { return m - (m.trace() / 3.0) * Mat3::Identity(); }

}  // namespace

TetFem::TetFem(const mesh::TetMesh& mesh, const FemMaterial& material)
    : material_(material), law_(LawParams::from(material)) {
  material_.validate();
  const auto n = static_cast<Eigen::Index>(mesh.vertices.size());
  rest_.resize(3 * n);
  for (Eigen::Index i = 0; i < n; ++i) rest_.segment<3>(3 * i) = mesh.vertices[static_cast<std::size_t>(i)];
  mass_ = VecX::Zero(3 * n);
  elements_.reserve(mesh.tets.size());
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    TetElement el;
    for (int a = 0; a < 4; ++a) {
      const auto v = mesh.tets[t][static_cast<std::size_t>(a)];
      if (v < 0 || v >= n)
        throw InputError("tet " + std::to_string(t) + " refers to vertex " + std::to_string(v) + ", out of range");
      el.nodes[static_cast<std::size_t>(a)] = v;
    }
    const Vec3 x0 = rest_.segment<3>(3 * el.nodes[0]);
    Mat3 Dm;
    double longest = 0.0;
    for (int a = 1; a < 4; ++a) {
      Dm.col(a - 1) = rest_.segment<3>(3 * el.nodes[static_cast<std::size_t>(a)]) - x0;
      longest = std::max(longest, Dm.col(a - 1).norm());
    }
    el.volume = Dm.determinant() / 6.0;
    // Relative test: a sliver 1e-12 of its edge cube is as singular as a flat element.
    if (!(el.volume > 1e-12 * longest * longest * longest))
      throw InputError("tet " + std::to_string(t) + " is inverted or has zero volume in the rest shape (volume " +
                       std::to_string(el.volume) + " m^3)");
    const Mat3 inv = Dm.inverse();
    // F = Ds Dm^-1 = sum_a x_a g_a^T: rows of Dm^-1 are g_1..g_3, and g_0 = -(g_1 + g_2 + g_3).
    for (int a = 1; a < 4; ++a) el.grad.col(a) = inv.row(a - 1).transpose();
    el.grad.col(0) = -(el.grad.col(1) + el.grad.col(2) + el.grad.col(3));
    el.sgrad = std::sqrt(el.volume) * el.grad;
    const double m = material_.density * el.volume / 4.0;  // lumped: a quarter per node
    for (int a = 0; a < 4; ++a) mass_.segment<3>(3 * el.nodes[static_cast<std::size_t>(a)]).array() += m;
    elements_.push_back(el);
  }
  // Vertices no tet uses get the mean nodal mass: no force acts on them, and explicit
  // integrators must not divide by zero.
  const double mean = n > 0 ? mass_.sum() / static_cast<double>(3 * n) : 0.0;
  for (Eigen::Index i = 0; i < mass_.size(); ++i)
    if (!(mass_[i] > 0.0)) mass_[i] = mean > 0.0 ? mean : 1.0;
  q_stride_ = prony_size(material_.prony.size());
  node_start_.assign(static_cast<std::size_t>(n) + 1, 0);
  for (const auto& el : elements_)
    for (auto v : el.nodes) ++node_start_[static_cast<std::size_t>(v) + 1];
  for (std::size_t i = 0; i < static_cast<std::size_t>(n); ++i) node_start_[i + 1] += node_start_[i];
  node_slot_.resize(4 * elements_.size());
  std::vector<std::int32_t> fill(node_start_.begin(), node_start_.end() - 1);
  for (std::size_t e = 0; e < elements_.size(); ++e)
    for (std::size_t a = 0; a < 4; ++a)
      node_slot_[static_cast<std::size_t>(fill[static_cast<std::size_t>(elements_[e].nodes[a])]++)] =
          static_cast<std::int32_t>(4 * e + a);
}

std::unique_ptr<Scratch> TetFem::make_scratch() const {
  auto c = std::make_unique<Cache>();
  if (rotated()) {
    c->rotation.assign(elements_.size(), Mat3::Identity());
    c->rotated_grad.reserve(elements_.size());
    for (const auto& el : elements_) c->rotated_grad.push_back(el.sgrad);
  }
  if (law_.law != FemLaw::linear && law_.law != FemLaw::corotational) c->tangent.assign(elements_.size(), Mat9::Zero());
  c->columns.assign(4 * elements_.size(), Vec3::Zero());
  return c;
}

TetFem::Cache& TetFem::cache(Scratch& s) const { return static_cast<Cache&>(s); }
const TetFem::Cache& TetFem::cache(const Scratch& s) const { return static_cast<const Cache&>(s); }

Mat3 TetFem::deformation_gradient(const VecX& x, std::size_t e) const { return gradient_of(x, elements_.at(e)); }

void TetFem::ensure_rotations(const VecX& x, Cache& c) const {
  if (c.rotations_valid && c.rotation_x.size() == x.size() &&
      std::equal(x.data(), x.data() + x.size(), c.rotation_x.data()))
    return;
  c.rotation.resize(elements_.size());
  c.rotated_grad.resize(elements_.size());
  parallel_for(0, elements_.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t e = begin; e < end; ++e) {
      c.rotation[e] = polar_rotation(gradient_of(x, elements_[e]));
      c.rotated_grad[e].noalias() = c.rotation[e] * elements_[e].sgrad;
    }
  }, kElementGrain);
  c.rotation_x = x;
  c.rotations_valid = true;
}

void TetFem::gather(const Cache& c, double mass_scale, const VecX& in, VecX& out) const {
  parallel_for(0, node_count(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      auto o = out.segment<3>(3 * static_cast<Eigen::Index>(i));
      if (mass_scale != 0.0)
        o += mass_scale * mass_.segment<3>(3 * static_cast<Eigen::Index>(i)).cwiseProduct(
                              in.segment<3>(3 * static_cast<Eigen::Index>(i)));
      for (auto k = node_start_[i]; k < node_start_[i + 1]; ++k) o += c.columns[static_cast<std::size_t>(node_slot_[static_cast<std::size_t>(k)])];
    }
  }, kNodeGrain);
}

void TetFem::forces(const VecX& x, const VecX& v, const VecX& q, VecX& f, Scratch& s) const {
  Cache& c = cache(s);
  f.setZero(x.size());
  const double beta = material_.rayleigh_stiffness;
  const bool corot = law_.law == FemLaw::corotational;
  const bool hyper = !corot && law_.law != FemLaw::linear;
  const bool damped = beta > 0.0 && v.size() == x.size();
  if (corot || (hyper && damped)) ensure_rotations(x, c);
  const bool viscous = q_stride_ > 0 && static_cast<std::size_t>(q.size()) == internal_size();
  auto element = [&](std::size_t e) {
    const TetElement& el = elements_[e];
    const auto node = [&](int a) { return 3 * el.nodes[static_cast<std::size_t>(a)]; };
    Vec3* out = &c.columns[4 * e];
    if (corot) {
      // With g^R = sqrt(V) R g: V R hooke(R^T F - I) g_a = hooke(D) g^R_a with
      // D = sum_b x_b (g^R_b)^T - sqrt(V) I (see rest_stiffness_columns).
      const Eigen::Matrix<double, 3, 4>& g = c.rotated_grad[e];
      Mat3 D = -std::sqrt(el.volume) * Mat3::Identity();
      for (int a = 0; a < 4; ++a) D.noalias() += x.segment<3>(node(a)) * g.col(a).transpose();
      Mat3 S = hooke_of_gradient(law_.lambda, law_.mu, D);
      if (damped) {
        Mat3 Dv = Mat3::Zero();
        for (int a = 0; a < 4; ++a) Dv.noalias() += v.segment<3>(node(a)) * g.col(a).transpose();
        S += beta * hooke_of_gradient(law_.lambda, law_.mu, Dv);
      }
      if (viscous) {
        // Branch stresses live in the corotated frame: V R s g_a = sqrt(V) (R s R^T) g^R_a.
        const Mat3& R = c.rotation[e];
        const Mat3 offset = prony_offset(material_.prony, std::span<const double>(q.data() + e * q_stride_, q_stride_));
        S += std::sqrt(el.volume) * (R * offset * R.transpose());
      }
      for (int a = 0; a < 4; ++a) out[a] = -(S * g.col(a));
      return;
    }
    const Mat3 F = gradient_of(x, el);
    Mat3 P;
    if (hyper) {
      hyperelastic_stress_tangent(law_, F, P, nullptr);
      if (damped) {
        const Mat3& R = c.rotation[e];
        P += R * (beta * hooke_of_gradient(law_.lambda, law_.mu, R.transpose() * gradient_of(v, el)));
      }
    } else {
      // Linear law: small-strain stress of the displacement gradient F - I.
      Mat3 H = F;
      H.diagonal().array() -= 1.0;
      P = hooke_of_gradient(law_.lambda, law_.mu, H);
      if (damped) P += beta * hooke_of_gradient(law_.lambda, law_.mu, gradient_of(v, el));
      if (viscous) P += prony_offset(material_.prony, std::span<const double>(q.data() + e * q_stride_, q_stride_));
    }
    P *= el.volume;
    for (int a = 0; a < 4; ++a) out[a] = -(P * el.grad.col(a));
  };
  parallel_for(0, elements_.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t e = begin; e < end; ++e) element(e);
  }, kElementGrain);
  gather(c, 0.0, x, f);
  if (material_.rayleigh_mass > 0.0 && v.size() == x.size()) f -= material_.rayleigh_mass * mass_.cwiseProduct(v);
}

void TetFem::linearize(const VecX& x, const VecX&, const VecX&, Scratch& s) const {
  Cache& c = cache(s);
  if (law_.law == FemLaw::linear) return;
  if (law_.law == FemLaw::corotational || material_.rayleigh_stiffness > 0.0) ensure_rotations(x, c);
  if (law_.law == FemLaw::corotational) return;
  c.tangent.resize(elements_.size());
  parallel_for(0, elements_.size(), [&](std::size_t begin, std::size_t end) {
    Mat3 P;
    for (std::size_t e = begin; e < end; ++e) {
      Mat9& A = c.tangent[e];
      hyperelastic_stress_tangent(law_, gradient_of(x, elements_[e]), P, &A);
      if (material_.project_tangent) project_psd(A);
    }
  }, kElementGrain);
}

template <bool Rotated>
void TetFem::rest_stiffness_columns(const VecX& dx, double scale, std::size_t begin, std::size_t end,
                                    const Cache& c) const {
  // (R K0 R^T dx)_a = V R hooke(R^T dF) g_a with dF = sum_b dx_b g_b^T. Since
  // R hooke(R^T dF) g_a = hooke(D) R g_a with D = sum_b dx_b (R g_b)^T, the rotated element
  // is the linear kernel on rotated gradients: about 90 flops per element, no 12x12 block.
  const double lambda = scale * law_.lambda, mu = scale * law_.mu;
  for (std::size_t e = begin; e < end; ++e) {
    const TetElement& el = elements_[e];
    const Eigen::Matrix<double, 3, 4>& g = Rotated ? c.rotated_grad[e] : el.sgrad;
    const auto n0 = 3 * el.nodes[0], n1 = 3 * el.nodes[1], n2 = 3 * el.nodes[2], n3 = 3 * el.nodes[3];
    // g_0 = -(g_1 + g_2 + g_3): D = sum_{b>0} (dx_b - dx_0) g_b^T and out_0 = -(out_1 + out_2 + out_3).
    const Vec3 d0 = dx.segment<3>(n0);
    Mat3 D;
    D.noalias() = (dx.segment<3>(n1) - d0) * g.col(1).transpose();
    D.noalias() += (dx.segment<3>(n2) - d0) * g.col(2).transpose();
    D.noalias() += (dx.segment<3>(n3) - d0) * g.col(3).transpose();
    Mat3 S = mu * (D + D.transpose());
    S.diagonal().array() += lambda * D.trace();
    Vec3* out = &c.columns[4 * e];
    out[1] = S * g.col(1);
    out[2] = S * g.col(2);
    out[3] = S * g.col(3);
    out[0] = -(out[1] + out[2] + out[3]);
  }
}

void TetFem::tangent_columns(const VecX& dx, double c_tangent, double b_rest, std::size_t begin, std::size_t end,
                             const Cache& c) const {
  // c·(tangent) dx plus, when b_rest != 0, b_rest·(rotated rest stiffness) dx.
  if (b_rest != 0.0) rest_stiffness_columns<true>(dx, b_rest, begin, end, c);
  if (c_tangent == 0.0) return;
  for (std::size_t e = begin; e < end; ++e) {
    const TetElement& el = elements_[e];
    const Vec9 dP = c.tangent[e] * vec9(gradient_of(dx, el));
    const Mat3 S = (c_tangent * el.volume) * Eigen::Map<const Mat3>(dP.data());
    Vec3* out = &c.columns[4 * e];
    for (int a = 0; a < 4; ++a) {
      if (b_rest != 0.0)
        out[a] += S * el.grad.col(a);
      else
        out[a] = S * el.grad.col(a);
    }
  }
}

void TetFem::add_system_product(double a, double b, double c_stiff, const VecX& in, VecX& out,
                                const Scratch& s) const {
  const Cache& c = cache(s);
  const double rest_scale = b * material_.rayleigh_stiffness;
  const double mass_scale = a + b * material_.rayleigh_mass;
  const bool hyper = law_.law != FemLaw::linear && law_.law != FemLaw::corotational;
  const bool elements = hyper ? (rest_scale != 0.0 || c_stiff != 0.0) : rest_scale + c_stiff != 0.0;
  if (elements) {
    parallel_for(0, elements_.size(), [&](std::size_t begin, std::size_t end) {
      switch (law_.law) {
        case FemLaw::linear: rest_stiffness_columns<false>(in, rest_scale + c_stiff, begin, end, c); break;
        case FemLaw::corotational: rest_stiffness_columns<true>(in, rest_scale + c_stiff, begin, end, c); break;
        default: tangent_columns(in, c_stiff, rest_scale, begin, end, c); break;
      }
    }, kElementGrain);
    gather(c, mass_scale, in, out);
  } else if (mass_scale != 0.0) {
    out += mass_scale * mass_.cwiseProduct(in);
  }
}

void TetFem::add_stiffness_product(const VecX& dx, VecX& out, const Scratch& s) const {
  add_system_product(0.0, 0.0, 1.0, dx, out, s);
}

void TetFem::add_damping_product(const VecX& dv, VecX& out, const Scratch& s) const {
  add_system_product(0.0, 1.0, 0.0, dv, out, s);
}

void TetFem::add_diagonal(double a, double b, VecX& out, const Scratch& s) const {
  const Cache& c = cache(s);
  const bool hyper = law_.law != FemLaw::linear && law_.law != FemLaw::corotational;
  const double beta = material_.rayleigh_stiffness;
  // Rotated rest stiffness: diag(R K0_aa R^T)_i = V (mu |g_a|^2 + (lambda + mu) (R g_a)_i^2).
  const double rest_weight = (hyper ? 0.0 : a) + b * beta;
  for (std::size_t e = 0; e < elements_.size(); ++e) {
    const TetElement& el = elements_[e];
    for (int n = 0; n < 4; ++n) {
      const Vec3 g = el.grad.col(n);
      auto d = out.segment<3>(3 * el.nodes[static_cast<std::size_t>(n)]);
      if (rest_weight != 0.0) {
        const Vec3 rg = rotated() ? Vec3(c.rotation[e] * g) : g;
        d.array() += rest_weight * el.volume *
                     (law_.mu * g.squaredNorm() + (law_.lambda + law_.mu) * rg.array().square());
      }
      if (hyper && a != 0.0) {
        // K_aa(i, i) = V sum_jl A(i + 3j, i + 3l) g_j g_l.
        const Mat9& A = c.tangent[e];
        for (int i = 0; i < 3; ++i) {
          double sum = 0.0;
          for (int j = 0; j < 3; ++j)
            for (int l = 0; l < 3; ++l) sum += A(i + 3 * j, i + 3 * l) * g[j] * g[l];
          d[i] += a * el.volume * sum;
        }
      }
    }
  }
  if (b != 0.0 && material_.rayleigh_mass > 0.0) out += (b * material_.rayleigh_mass) * mass_;
}

void TetFem::element_matrix(std::size_t e, double a, double b, const Cache& c, Mat12& k) const {
  // Column by column: the element's response to each unit nodal displacement.
  const TetElement& el = elements_[e];
  const bool hyper = law_.law != FemLaw::linear && law_.law != FemLaw::corotational;
  const double beta = material_.rayleigh_stiffness;
  const Mat3 R = rotated() ? c.rotation[e] : Mat3::Identity();
  for (int col = 0; col < 12; ++col) {
    const int node = col / 3, dir = col % 3;
    Mat3 dF = Mat3::Zero();
    dF.row(dir) = el.grad.col(node).transpose();
    Mat3 S = Mat3::Zero();
    const Mat3 rest = R * hooke_of_gradient(law_.lambda, law_.mu, R.transpose() * dF);
    if (hyper) {
      const Vec9 dP = c.tangent[e] * vec9(dF);
      S += a * Eigen::Map<const Mat3>(dP.data());
      S += (b * beta) * rest;
    } else {
      S += (a + b * beta) * rest;
    }
    S *= el.volume;
    for (int n = 0; n < 4; ++n) k.block<3, 1>(3 * n, col) = S * el.grad.col(n);
  }
}

void TetFem::add_triplets(double a, double b, std::vector<Triplet>& out, const Scratch& s) const {
  const Cache& c = cache(s);
  Mat12 k;
  out.reserve(out.size() + 144 * elements_.size() + static_cast<std::size_t>(mass_.size()));
  for (std::size_t e = 0; e < elements_.size(); ++e) {
    element_matrix(e, a, b, c, k);
    const TetElement& el = elements_[e];
    for (int cn = 0; cn < 4; ++cn)
      for (int rn = 0; rn < 4; ++rn)
        for (int j = 0; j < 3; ++j)
          for (int i = 0; i < 3; ++i)
            out.emplace_back(3 * el.nodes[static_cast<std::size_t>(rn)] + i, 3 * el.nodes[static_cast<std::size_t>(cn)] + j,
                             k(3 * rn + i, 3 * cn + j));
  }
  if (b != 0.0 && material_.rayleigh_mass > 0.0)
    for (Eigen::Index i = 0; i < mass_.size(); ++i) out.emplace_back(i, i, b * material_.rayleigh_mass * mass_[i]);
}

void TetFem::update_internal(const VecX& x, double dt, VecX& q, Scratch& s) const {
  if (q_stride_ == 0 || static_cast<std::size_t>(q.size()) != internal_size()) return;
  Cache& c = cache(s);
  const bool corot = law_.law == FemLaw::corotational;
  if (corot) ensure_rotations(x, c);
  parallel_for(0, elements_.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t e = begin; e < end; ++e) {
      const Mat3 F = gradient_of(x, elements_[e]);
      Mat3 grad = corot ? Mat3(c.rotation[e].transpose() * F) : F;
      grad.diagonal().array() -= 1.0;
      const Mat3 eps = 0.5 * (grad + grad.transpose());
      const Mat3 sbar =
          material_.prony_relaxes_bulk ? hooke(law_.lambda, law_.mu, eps) : Mat3(2.0 * law_.mu * deviator(eps));
      prony_update(material_.prony, sbar, dt, std::span<double>(q.data() + e * q_stride_, q_stride_));
    }
  }, kElementGrain);
}

double TetFem::elastic_energy(const VecX& x, const VecX&) const {
  double energy = 0.0;
  for (const TetElement& el : elements_) energy += el.volume * strain_energy_density(law_, gradient_of(x, el));
  return energy;
}

}  // namespace tactus::physics
