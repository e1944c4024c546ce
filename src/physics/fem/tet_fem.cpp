#include "physics/fem/tet_fem.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <span>
#include <string>

#include <fmt/format.h>

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
  /// Hyperelastic: dP/dF per element (projected if asked). Mutable: StVK's exact tangent
  /// is kept as `stvk_fs` and expanded here only where a matrix is assembled.
  mutable std::vector<Mat9> tangent;
  /// StVK's exact tangent without its 9×9 blocks: F and S = λ tr(E) I + 2μ E per element, so
  /// that dP = dF·S + F·dS (about 100 flops a product, where the blocks cost 81 per product
  /// and 400 per element to build). Newton's directions mostly need products alone (the
  /// factor in hand preconditions them), so the blocks are built only for a factorization.
  std::vector<std::array<Mat3, 2>> stvk_fs;
  mutable bool tangent_deferred = false;  ///< `tangent` is stale; `stvk_fs` holds the tangent
  /// Each element's contribution to its four nodes (12 values per element), written by the
  /// element pass and summed per node by gather(); scratch space of const products.
  mutable std::vector<Vec3> columns;
  BlockMatrix system;  ///< assemble_system()'s matrix
};

namespace {

using Mat12 = Eigen::Matrix<double, 12, 12>;
using Mat34 = Eigen::Matrix<double, 3, 4>;

// Loops shorter than two grains run on the calling thread: waking the pool's workers costs
// more than the work they share below about 8,000 tetrahedra on the 2-core machine
// (docs/BENCHMARKS.md).
constexpr std::size_t kElementGrain = 4096, kNodeGrain = 1024;
constexpr std::size_t kRotationBlock = 32;

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

// The element kernels below are plain scalar code on small arrays: fixed-size Eigen
// expressions this deep inside the templated loops stop being inlined, and the calls cost more
// than the arithmetic.

/// An element's contributions to its four nodes.
using Columns = std::array<std::array<double, 3>, 4>;

/// d_b += scale (y_{b+1} - y_0), b = 0..2, for the nodal values y at node offsets n (3 per node).
inline void add_differences(const double* y, const std::array<Eigen::Index, 4>& n, double scale, double (&d)[3][3]) {
  for (int b = 0; b < 3; ++b)
    for (int i = 0; i < 3; ++i) d[b][i] += scale * (y[n[b + 1] + i] - y[n[0] + i]);
}

/// D = sum_{b>0} d_{b-1} g_b^T for node differences d: with g_0 = -(g_1 + g_2 + g_3) this is
/// sum_b y_b g_b^T, from differences (small next to the positions, so less round-off).
inline void difference_gradient(const double (&d)[3][3], const Mat34& g, double (&D)[3][3]) {
  const double* G = g.data();  // column b at G + 3 b
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) D[i][j] = d[0][i] * G[3 + j] + d[1][i] * G[6 + j] + d[2][i] * G[9 + j];
}

/// out_b = sign hooke(D) g_b for b = 1..3 and out_0 = -(out_1 + out_2 + out_3), where
/// hooke(D) = lambda tr(D) I + mu (D + D^T).
inline void hooke_columns(const double (&D)[3][3], const Mat34& g, double lambda, double mu, double sign,
                          Columns& out) {
  const double* G = g.data();
  const double tr = lambda * (D[0][0] + D[1][1] + D[2][2]);
  double S[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) S[i][j] = sign * (mu * (D[i][j] + D[j][i]) + (i == j ? tr : 0.0));
  for (int b = 1; b < 4; ++b)
    for (int i = 0; i < 3; ++i) out[b][i] = S[i][0] * G[3 * b] + S[i][1] * G[3 * b + 1] + S[i][2] * G[3 * b + 2];
  for (int i = 0; i < 3; ++i) out[0][i] = -(out[1][i] + out[2][i] + out[3][i]);
}

/// The node pairs of an element, in the order of TetFem::pair_block_.
constexpr std::array<std::array<std::size_t, 2>, 6> kPairs{{{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}}};

inline std::array<Eigen::Index, 4> node_offsets(const TetElement& el) {
  return {3 * Eigen::Index{el.nodes[0]}, 3 * Eigen::Index{el.nodes[1]}, 3 * Eigen::Index{el.nodes[2]},
          3 * Eigen::Index{el.nodes[3]}};
}

/// Element contributions of the serial path: added to the output vector at once.
struct ScatterToNodes {
  const std::vector<TetElement>& elements;
  double* out;
  void operator()(std::size_t e, const Columns& col) const {
    const auto& n = elements[e].nodes;
    for (std::size_t a = 0; a < 4; ++a)
      for (int i = 0; i < 3; ++i) out[3 * Eigen::Index{n[a]} + i] += col[a][static_cast<std::size_t>(i)];
  }
};

/// Element contributions of the parallel path: stored per element for TetFem::gather.
struct StoreColumns {
  Vec3* columns;
  void operator()(std::size_t e, const Columns& col) const {
    for (std::size_t a = 0; a < 4; ++a) columns[4 * e + a] = Vec3(col[a][0], col[a][1], col[a][2]);
  }
};

}  // namespace

TetFem::TetFem(const mesh::TetMesh& mesh, const FemMaterial& material, FemMass mass)
    : TetFem(mesh, std::span<const FemMaterial>(&material, 1), {}, mass) {}

TetFem::TetFem(const mesh::TetMesh& mesh, std::span<const FemMaterial> materials,
               std::span<const std::int32_t> element_material, FemMass mass)
    : mass_kind_(mass) {
  if (materials.empty()) throw InputError("a FEM body needs at least one material");
  if (!element_material.empty() && element_material.size() != mesh.tets.size())
    throw InputError(fmt::format("{} element materials given for {} tetrahedra", element_material.size(),
                                 mesh.tets.size()));
  // One law, damping and relaxation for the whole body (they shape the system and its
  // internal variables); each region its own elastic constants and density.
  for (std::size_t k = 0; k < materials.size(); ++k) {
    const FemMaterial& m = materials[k];
    m.validate();
    const FemMaterial& first = materials.front();
    if (k > 0 && (m.law != first.law || m.rayleigh_mass != first.rayleigh_mass ||
                  m.rayleigh_stiffness != first.rayleigh_stiffness || m.prony != first.prony ||
                  m.prony_relaxes_bulk != first.prony_relaxes_bulk || m.project_tangent != first.project_tangent ||
                  m.nodal_pressure != first.nodal_pressure))
      throw InputError(fmt::format("material {} of a FEM body differs from the first in its law, damping, relaxation or "
                                   "volumetric term; "
                                   "the regions of one body share those and differ in elastic constants and density",
                                   k));
    materials_.push_back(m);
    laws_.push_back(LawParams::from(m));
    if (m.nodal_pressure) laws_.back().kappa = 0.0;  // NodalPressureFem adds it at the nodes
    densities_.push_back(m.density);
  }
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
    if (!element_material.empty()) {
      el.material = element_material[t];
      if (el.material < 0 || static_cast<std::size_t>(el.material) >= materials.size())
        throw InputError(fmt::format("tet {} has material {}, out of range (the body has {})", t, el.material,
                                     materials.size()));
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
    const double m = density_of(el) * el.volume / 4.0;  // lumped: a quarter per node
    for (int a = 0; a < 4; ++a) mass_.segment<3>(3 * el.nodes[static_cast<std::size_t>(a)]).array() += m;
    elements_.push_back(el);
  }
  // Vertices no tet uses get the mean nodal mass: no force acts on them, and explicit
  // integrators must not divide by zero.
  const double mean = n > 0 ? mass_.sum() / static_cast<double>(3 * n) : 0.0;
  if (mass_kind_ == FemMass::consistent) {
    // M_e in at node a is rho V/20 (in_a + sum_b in_b): a fifth of the lumped mass on the
    // node's own value plus each element's share of its nodes' sum. Unused vertices keep
    // their lumped mass, so M stays positive definite.
    consistent_own_ = 0.2 * mass_;
    mass_diagonal_ = 0.4 * mass_;
    for (Eigen::Index i = 0; i < mass_.size(); ++i)
      if (!(mass_[i] > 0.0)) consistent_own_[i] = mass_diagonal_[i] = mean > 0.0 ? mean : 1.0;
  }
  for (Eigen::Index i = 0; i < mass_.size(); ++i)
    if (!(mass_[i] > 0.0)) mass_[i] = mean > 0.0 ? mean : 1.0;
  if (mass_kind_ == FemMass::lumped) mass_diagonal_ = mass_;
  q_stride_ = prony_size(material().prony.size());
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

  // The assembled system's pattern: an upper block for every node pair that shares an element.
  std::vector<std::vector<std::int32_t>> above(static_cast<std::size_t>(n));
  for (const auto& el : elements_)
    for (const auto& [a, b] : kPairs)
      above[static_cast<std::size_t>(std::min(el.nodes[a], el.nodes[b]))].push_back(std::max(el.nodes[a], el.nodes[b]));
  block_row_start_.assign(static_cast<std::size_t>(n) + 1, 0);
  for (std::size_t i = 0; i < above.size(); ++i) {
    std::sort(above[i].begin(), above[i].end());
    above[i].erase(std::unique(above[i].begin(), above[i].end()), above[i].end());
    block_column_.insert(block_column_.end(), above[i].begin(), above[i].end());
    block_row_start_[i + 1] = static_cast<std::int32_t>(block_column_.size());
  }
  pair_block_.resize(elements_.size());
  for (std::size_t e = 0; e < elements_.size(); ++e)
    for (std::size_t p = 0; p < kPairs.size(); ++p) {
      const auto na = elements_[e].nodes[kPairs[p][0]], nb = elements_[e].nodes[kPairs[p][1]];
      const auto row = static_cast<std::size_t>(std::min(na, nb));
      const auto first = block_column_.begin() + block_row_start_[row];
      const auto last = block_column_.begin() + block_row_start_[row + 1];
      const auto found = std::lower_bound(first, last, std::max(na, nb));
      const auto index = static_cast<std::int32_t>(found - block_column_.begin());
      pair_block_[e][p] = na < nb ? index : -1 - index;
    }
  block_pair_start_.assign(block_column_.size() + 1, 0);
  for (const auto& pairs : pair_block_)
    for (const auto index : pairs) ++block_pair_start_[static_cast<std::size_t>(index >= 0 ? index : -1 - index) + 1];
  for (std::size_t k = 0; k < block_column_.size(); ++k) block_pair_start_[k + 1] += block_pair_start_[k];
  block_pair_.resize(static_cast<std::size_t>(block_pair_start_.back()));
  std::vector<std::int32_t> next(block_pair_start_.begin(), block_pair_start_.end() - 1);
  for (std::size_t e = 0; e < pair_block_.size(); ++e)
    for (std::size_t p = 0; p < kPairs.size(); ++p) {
      const std::int32_t index = pair_block_[e][p];
      const auto code = static_cast<std::int32_t>(6 * e + p);
      block_pair_[static_cast<std::size_t>(next[static_cast<std::size_t>(index >= 0 ? index : -1 - index)]++)] =
          index >= 0 ? code : -1 - code;
    }
}

std::unique_ptr<Scratch> TetFem::make_scratch() const {
  auto c = std::make_unique<Cache>();
  if (rotated()) {
    c->rotation.assign(elements_.size(), Mat3::Identity());
    c->rotated_grad.reserve(elements_.size());
    for (const auto& el : elements_) c->rotated_grad.push_back(el.sgrad);
  }
  if (law().law != FemLaw::linear && law().law != FemLaw::corotational) c->tangent.assign(elements_.size(), Mat9::Zero());
  c->columns.assign(4 * elements_.size(), Vec3::Zero());
  if (law().law == FemLaw::linear || law().law == FemLaw::corotational) {
    c->system.diagonal.assign(node_count(), Mat3::Zero());
    c->system.row_start = block_row_start_;
    c->system.column = block_column_;
    c->system.upper.assign(block_column_.size(), Mat3::Zero());
  }
  return c;
}

TetFem::Cache& TetFem::cache(Scratch& s) const { return static_cast<Cache&>(s); }
const TetFem::Cache& TetFem::cache(const Scratch& s) const { return static_cast<const Cache&>(s); }

Mat3 TetFem::deformation_gradient(const VecX& x, std::size_t e) const { return gradient_of(x, elements_.at(e)); }

double TetFem::min_volume_ratio(const VecX& x) const {
  if (!hyperelastic()) return std::numeric_limits<double>::infinity();
  double j = std::numeric_limits<double>::infinity();
  for (const TetElement& el : elements_) j = std::min(j, gradient_of(x, el).determinant());
  return j;
}

bool TetFem::rotations_current(const VecX& x, const Cache& c) const {
  return c.rotations_valid && c.rotation_x.size() == x.size() &&
         std::equal(x.data(), x.data() + x.size(), c.rotation_x.data());
}

void TetFem::update_rotations(const VecX& x, std::size_t begin, std::size_t end, Cache& c) const {
  // A few dozen at a time: polar_rotations works on several side by side.
  std::array<Mat3, kRotationBlock> F;
  for (std::size_t block = begin; block < end; block += kRotationBlock) {
    const std::size_t count = std::min(kRotationBlock, end - block);
    for (std::size_t k = 0; k < count; ++k) {
      // sqrt(V) F from the scaled gradients the other loops read too (one array less to
      // stream); the rotation of a positive multiple of F is the rotation of F.
      const TetElement& el = elements_[block + k];
      double d[3][3] = {}, D[3][3];
      add_differences(x.data(), node_offsets(el), 1.0, d);
      difference_gradient(d, el.sgrad, D);
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) F[k](i, j) = D[i][j];
    }
    polar_rotations(std::span<const Mat3>(F.data(), count), std::span<Mat3>(c.rotation.data() + block, count));
    for (std::size_t e = block; e < block + count; ++e) {
      // rotated_grad = R sgrad, in plain loops (column-major 3x3 times 3x4).
      const double* R = c.rotation[e].data();
      const double* g = elements_[e].sgrad.data();
      double* out = c.rotated_grad[e].data();
      for (int a = 0; a < 4; ++a)
        for (int i = 0; i < 3; ++i)
          out[3 * a + i] = R[i] * g[3 * a] + R[i + 3] * g[3 * a + 1] + R[i + 6] * g[3 * a + 2];
    }
  }
}

void TetFem::ensure_rotations(const VecX& x, Cache& c) const {
  if (rotations_current(x, c)) return;
  c.rotation.resize(elements_.size());
  c.rotated_grad.resize(elements_.size());
  parallel_for(0, elements_.size(), [&](std::size_t begin, std::size_t end) { update_rotations(x, begin, end, c); },
               kElementGrain);
  c.rotation_x = x;
  c.rotations_valid = true;
}

template <class Kernel>
void TetFem::accumulate(const Cache& c, double mass_scale, const VecX& in, VecX& out, Kernel&& kernel) const {
  if (thread_count() == 1 || elements_.size() < 2 * kElementGrain) {
    // Serial: no columns to write and read back, no node pass.
    if (mass_scale != 0.0) out += mass_scale * mass_.cwiseProduct(in);
    kernel(std::size_t{0}, elements_.size(), ScatterToNodes{elements_, out.data()});
    return;
  }
  parallel_for(0, elements_.size(), [&](std::size_t begin, std::size_t end) {
    kernel(begin, end, StoreColumns{c.columns.data()});
  }, kElementGrain);
  gather(c, mass_scale, in, out);
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
  const double beta = material().rayleigh_stiffness;
  const bool corot = law().law == FemLaw::corotational;
  const bool hyper = !corot && law().law != FemLaw::linear;
  const bool damped = beta > 0.0 && v.size() == x.size();
  if (corot || (hyper && damped)) ensure_rotations(x, c);
  const bool viscous = q_stride_ > 0 && static_cast<std::size_t>(q.size()) == internal_size();
  auto element = [&](std::size_t e, Columns& out) {
    const TetElement& el = elements_[e];
    const auto node = [&](int a) { return 3 * el.nodes[static_cast<std::size_t>(a)]; };
    if (corot) {
      // With g^R = sqrt(V) R g: V R hooke(R^T F - I) g_a = hooke(D) g^R_a with
      // D = sum_b x_b (g^R_b)^T - sqrt(V) I (see rest_stiffness_columns).
      const Mat34& g = c.rotated_grad[e];
      Mat3 D = -std::sqrt(el.volume) * Mat3::Identity();
      for (int a = 0; a < 4; ++a) D.noalias() += x.segment<3>(node(a)) * g.col(a).transpose();
      const LawParams& law = law_of(el);
      Mat3 S = hooke_of_gradient(law.lambda, law.mu, D);
      if (damped) {
        Mat3 Dv = Mat3::Zero();
        for (int a = 0; a < 4; ++a) Dv.noalias() += v.segment<3>(node(a)) * g.col(a).transpose();
        S += beta * hooke_of_gradient(law.lambda, law.mu, Dv);
      }
      if (viscous) {
        // Branch stresses live in the corotated frame: V R s g_a = sqrt(V) (R s R^T) g^R_a.
        const Mat3& R = c.rotation[e];
        const Mat3 offset = prony_offset(material().prony, std::span<const double>(q.data() + e * q_stride_, q_stride_));
        S += std::sqrt(el.volume) * (R * offset * R.transpose());
      }
      for (int a = 0; a < 4; ++a) Eigen::Map<Vec3>(out[static_cast<std::size_t>(a)].data()) = -(S * g.col(a));
      return;
    }
    const Mat3 F = gradient_of(x, el);
    const LawParams& law = law_of(el);
    Mat3 P;
    if (hyper) {
      hyperelastic_stress_tangent(law, F, P, nullptr);
      // Branch stresses are second Piola-Kirchhoff stresses: P = F (S0 + offset).
      if (viscous) P += F * prony_offset(material().prony, std::span<const double>(q.data() + e * q_stride_, q_stride_));
      if (damped) {
        const Mat3& R = c.rotation[e];
        P += R * (beta * hooke_of_gradient(law.lambda, law.mu, R.transpose() * gradient_of(v, el)));
      }
    } else {
      // Linear law: small-strain stress of the displacement gradient F - I.
      Mat3 H = F;
      H.diagonal().array() -= 1.0;
      P = hooke_of_gradient(law.lambda, law.mu, H);
      if (damped) P += beta * hooke_of_gradient(law.lambda, law.mu, gradient_of(v, el));
      if (viscous) P += prony_offset(material().prony, std::span<const double>(q.data() + e * q_stride_, q_stride_));
    }
    P *= el.volume;
    for (int a = 0; a < 4; ++a) Eigen::Map<Vec3>(out[static_cast<std::size_t>(a)].data()) = -(P * el.grad.col(a));
  };
  const bool mass_damped = material().rayleigh_mass > 0.0 && v.size() == x.size();
  accumulate(c, mass_damped ? nodal_mass_scale(-material().rayleigh_mass) : 0.0, mass_damped ? v : x, f,
             [&](std::size_t begin, std::size_t end, auto sink) {
               Columns out;
               for (std::size_t e = begin; e < end; ++e) {
                 element(e, out);
                 sink(e, out);
               }
             });
  if (mass_damped) add_consistent_mass(-material().rayleigh_mass, v, f);
}

void TetFem::linearized_forces(const VecX& x, const VecX& v, const VecX& q, const VecX& dx, VecX& f,
                               Scratch& s) const {
  const bool corot = law().law == FemLaw::corotational;
  if (!corot && law().law != FemLaw::linear) {
    ForceModel::linearized_forces(x, v, q, dx, f, s);
    return;
  }
  Cache& c = cache(s);
  f.setZero(x.size());
  const bool fresh = corot && !rotations_current(x, c);  // rotations to compute in the pass
  if (fresh) {
    c.rotation.resize(elements_.size());
    c.rotated_grad.resize(elements_.size());
  }
  const double beta = material().rayleigh_stiffness;
  const bool damped = beta > 0.0 && v.size() == x.size();
  const bool viscous = q_stride_ > 0 && static_cast<std::size_t>(q.size()) == internal_size();
  auto kernel = [&](std::size_t begin, std::size_t end, auto sink) {
    Columns out;
    for (std::size_t e = begin; e < end; ++e) {
      // Rotations a few dozen elements ahead, while their data is still in cache.
      if (fresh && (e - begin) % kRotationBlock == 0) update_rotations(x, e, std::min(end, e + kRotationBlock), c);
      const TetElement& el = elements_[e];
      const Mat34& g = corot ? c.rotated_grad[e] : el.sgrad;
      const auto n = node_offsets(el);
      // The force at y = x - dx: D = sum_b y_b g_b^T - sqrt(V) I, as in forces(), plus the
      // damping term's beta sum_b v_b g_b^T (hooke is linear).
      double d[3][3] = {}, D[3][3];
      add_differences(x.data(), n, 1.0, d);
      add_differences(dx.data(), n, -1.0, d);
      if (damped) add_differences(v.data(), n, beta, d);
      difference_gradient(d, g, D);
      const double root_volume = std::sqrt(el.volume);
      for (int i = 0; i < 3; ++i) D[i][i] -= root_volume;
      hooke_columns(D, g, law_of(el).lambda, law_of(el).mu, -1.0, out);
      if (viscous) {
        // Branch stresses in the corotated frame, as in forces().
        Mat3 offset = prony_offset(material().prony, std::span<const double>(q.data() + e * q_stride_, q_stride_));
        if (corot) offset = c.rotation[e] * offset * c.rotation[e].transpose();
        for (int a = 0; a < 4; ++a)
          Eigen::Map<Vec3>(out[static_cast<std::size_t>(a)].data()) -= root_volume * (offset * g.col(a));
      }
      sink(e, out);
    }
  };
  const bool mass_damped = material().rayleigh_mass > 0.0 && v.size() == x.size();
  accumulate(c, mass_damped ? nodal_mass_scale(-material().rayleigh_mass) : 0.0, mass_damped ? v : x, f, kernel);
  if (mass_damped) add_consistent_mass(-material().rayleigh_mass, v, f);
  if (fresh) {
    c.rotation_x = x;
    c.rotations_valid = true;
  }
}

void TetFem::linearize(const VecX& x, const VecX& v, const VecX& q, Scratch& s) const {
  linearize_tangent(x, v, q, s, material().project_tangent);
}

bool TetFem::linearize_exact(const VecX& x, const VecX& v, const VecX& q, Scratch& s) const {
  if (!material().project_tangent || law().law == FemLaw::linear || law().law == FemLaw::corotational) return false;
  linearize_tangent(x, v, q, s, false);
  return true;
}

void TetFem::linearize_tangent(const VecX& x, const VecX&, const VecX& q, Scratch& s, bool project) const {
  Cache& c = cache(s);
  c.tangent_deferred = false;
  if (law().law == FemLaw::linear) return;
  if (law().law == FemLaw::corotational || material().rayleigh_stiffness > 0.0) ensure_rotations(x, c);
  if (law().law == FemLaw::corotational) return;
  const bool viscous = q_stride_ > 0 && static_cast<std::size_t>(q.size()) == internal_size();
  if (law().law == FemLaw::stvk && !viscous && !project) {
    c.stvk_fs.resize(elements_.size());
    parallel_for(0, elements_.size(), [&](std::size_t begin, std::size_t end) {
      for (std::size_t e = begin; e < end; ++e) {
        const LawParams& law = law_of(elements_[e]);
        const Mat3 F = gradient_of(x, elements_[e]);
        Mat3 S = law.mu * (F.transpose() * F - Mat3::Identity());
        S.diagonal().array() += 0.5 * law.lambda * (F.squaredNorm() - 3.0);
        c.stvk_fs[e] = {F, S};
      }
    }, kElementGrain);
    c.tangent_deferred = true;
    return;
  }
  c.tangent.resize(elements_.size());
  parallel_for(0, elements_.size(), [&](std::size_t begin, std::size_t end) {
    Mat3 P;
    for (std::size_t e = begin; e < end; ++e) {
      Mat9& A = c.tangent[e];
      hyperelastic_stress_tangent(law_of(elements_[e]), gradient_of(x, elements_[e]), P, &A);
      if (viscous) {
        // d(F O)/dF for the branches' constant offset O: dP_ij/dF_kl = delta_ik O_lj (a
        // geometric stiffness, like the one of the elastic stress).
        const Mat3 O = prony_offset(material().prony, std::span<const double>(q.data() + e * q_stride_, q_stride_));
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j)
            for (int l = 0; l < 3; ++l) A(i + 3 * j, i + 3 * l) += O(l, j);
      }
      if (project) project_psd(A);
    }
  }, kElementGrain);
}

template <bool Rotated, class Sink>
void TetFem::rest_stiffness_columns(const VecX& dx, double scale, std::size_t begin, std::size_t end,
                                    const Cache& c, Sink sink) const {
  // (R K0 R^T dx)_a = V R hooke(R^T dF) g_a with dF = sum_b dx_b g_b^T. Since
  // R hooke(R^T dF) g_a = hooke(D) R g_a with D = sum_b dx_b (R g_b)^T, the rotated element
  // is the linear kernel on rotated gradients: about 90 flops per element, no 12x12 block.
  Columns out;
  for (std::size_t e = begin; e < end; ++e) {
    const TetElement& el = elements_[e];
    const Mat34& g = Rotated ? c.rotated_grad[e] : el.sgrad;
    double d[3][3] = {}, D[3][3];
    add_differences(dx.data(), node_offsets(el), 1.0, d);
    difference_gradient(d, g, D);
    hooke_columns(D, g, scale * law_of(el).lambda, scale * law_of(el).mu, 1.0, out);
    sink(e, out);
  }
}

template <class Sink>
void TetFem::tangent_columns(const VecX& dx, double c_tangent, double b_rest, std::size_t begin, std::size_t end,
                             const Cache& c, Sink sink) const {
  // c·(tangent) dx plus, when b_rest != 0, b_rest·(rotated rest stiffness) dx.
  Columns out, rest;
  for (std::size_t e = begin; e < end; ++e) {
    const TetElement& el = elements_[e];
    Mat3 S = Mat3::Zero();
    if (c_tangent != 0.0 && c.tangent_deferred) {
      // StVK: dP = dF·S + F·dS, dS = λ tr(dE) I + 2μ dE, dE = sym(Fᵀ dF).
      const auto& [F, S_e] = c.stvk_fs[e];
      const LawParams& law = law_of(el);
      const Mat3 dF = gradient_of(dx, el);
      const Mat3 FtdF = F.transpose().lazyProduct(dF);
      Mat3 dS = law.mu * (FtdF + FtdF.transpose());
      dS.diagonal().array() += law.lambda * FtdF.trace();
      S = (c_tangent * el.volume) * (dF.lazyProduct(S_e) + F.lazyProduct(dS));
    } else if (c_tangent != 0.0) {
      // Unrolled: a 9×9 product is too small for Eigen's GEMV kernel.
      const Vec9 dP = c.tangent[e].lazyProduct(vec9(gradient_of(dx, el)));
      S = (c_tangent * el.volume) * Eigen::Map<const Mat3>(dP.data());
    }
    for (int a = 0; a < 4; ++a) Eigen::Map<Vec3>(out[static_cast<std::size_t>(a)].data()) = S * el.grad.col(a);
    if (b_rest != 0.0) {
      double d[3][3] = {}, D[3][3];
      add_differences(dx.data(), node_offsets(el), 1.0, d);
      difference_gradient(d, c.rotated_grad[e], D);
      hooke_columns(D, c.rotated_grad[e], b_rest * law_of(el).lambda, b_rest * law_of(el).mu, 1.0, rest);
      for (std::size_t a = 0; a < 4; ++a)
        for (std::size_t i = 0; i < 3; ++i) out[a][i] += rest[a][i];
    }
    sink(e, out);
  }
}

void TetFem::add_system_product(double a, double b, double c_stiff, const VecX& in, VecX& out,
                                const Scratch& s) const {
  const Cache& c = cache(s);
  const double rest_scale = b * material().rayleigh_stiffness;
  const double mass_scale = a + b * material().rayleigh_mass;
  const bool hyper = law().law != FemLaw::linear && law().law != FemLaw::corotational;
  const bool elements = hyper ? (rest_scale != 0.0 || c_stiff != 0.0) : rest_scale + c_stiff != 0.0;
  if (!elements) {
    if (mass_scale != 0.0) add_mass_product(mass_scale, in, out);
    return;
  }
  accumulate(c, nodal_mass_scale(mass_scale), in, out, [&](std::size_t begin, std::size_t end, auto sink) {
    switch (law().law) {
      case FemLaw::linear: rest_stiffness_columns<false>(in, rest_scale + c_stiff, begin, end, c, sink); break;
      case FemLaw::corotational: rest_stiffness_columns<true>(in, rest_scale + c_stiff, begin, end, c, sink); break;
      default: tangent_columns(in, c_stiff, rest_scale, begin, end, c, sink); break;
    }
  });
  if (mass_scale != 0.0) add_consistent_mass(mass_scale, in, out);
}

void TetFem::add_consistent_mass(double scale, const VecX& in, VecX& out) const {
  if (mass_kind_ != FemMass::consistent) return;
  // Serial, in element order: the sums are the same whatever the thread count.
  out += scale * consistent_own_.cwiseProduct(in);
  for (const TetElement& el : elements_) {
    const auto n = node_offsets(el);
    Vec3 sum = Vec3::Zero();
    for (std::size_t a = 0; a < 4; ++a) sum += in.segment<3>(n[a]);
    sum *= (scale * density_of(el) / 20.0) * el.volume;
    for (std::size_t a = 0; a < 4; ++a) out.segment<3>(n[a]) += sum;
  }
}

void TetFem::add_mass_product(double scale, const VecX& in, VecX& out) const {
  if (mass_kind_ == FemMass::lumped)
    out += scale * mass_.cwiseProduct(in);
  else
    add_consistent_mass(scale, in, out);
}

template <class Emit>
void TetFem::emit_mass_triplets(double scale, Emit&& emit) const {
  if (mass_kind_ == FemMass::lumped) {
    for (Eigen::Index i = 0; i < mass_.size(); ++i) emit(i, i, scale * mass_[i]);
    return;
  }
  // rho V/20 (1 + delta_ab) on the three diagonals of each node pair's block; the vertices
  // no element uses keep their lumped mass.
  for (const TetElement& el : elements_) {
    const double m = scale * density_of(el) * el.volume / 20.0;
    for (std::size_t a = 0; a < 4; ++a)
      for (std::size_t b = 0; b < 4; ++b)
        for (int i = 0; i < 3; ++i) emit(3 * el.nodes[a] + i, 3 * el.nodes[b] + i, a == b ? 2.0 * m : m);
  }
  for (Eigen::Index i = 0; i < mass_.size(); ++i)
    if (consistent_own_[i] == mass_diagonal_[i]) emit(i, i, scale * mass_diagonal_[i]);
}

std::size_t TetFem::mass_triplet_count() const {
  if (mass_kind_ == FemMass::lumped) return static_cast<std::size_t>(mass_.size());
  return 48 * elements_.size() +
         static_cast<std::size_t>((consistent_own_.array() == mass_diagonal_.array()).count());
}

void TetFem::add_mass_triplets(double scale, std::vector<Triplet>& out) const {
  out.reserve(out.size() + mass_triplet_count());
  emit_mass_triplets(scale, [&](Eigen::Index row, Eigen::Index col, double v) { out.emplace_back(row, col, v); });
}

void TetFem::add_stiffness_product(const VecX& dx, VecX& out, const Scratch& s) const {
  add_system_product(0.0, 0.0, 1.0, dx, out, s);
}

void TetFem::add_damping_product(const VecX& dv, VecX& out, const Scratch& s) const {
  add_system_product(0.0, 1.0, 0.0, dv, out, s);
}

void TetFem::expand_deferred_tangent(const Cache& c) const {
  if (!c.tangent_deferred) return;
  c.tangent.resize(elements_.size());
  parallel_for(0, elements_.size(), [&](std::size_t begin, std::size_t end) {
    Mat3 P;
    for (std::size_t e = begin; e < end; ++e)
      hyperelastic_stress_tangent(law_of(elements_[e]), c.stvk_fs[e][0], P, &c.tangent[e]);
  }, kElementGrain);
  c.tangent_deferred = false;
}

void TetFem::add_diagonal(double a, double b, VecX& out, const Scratch& s) const {
  const Cache& c = cache(s);
  expand_deferred_tangent(c);
  const bool hyper = law().law != FemLaw::linear && law().law != FemLaw::corotational;
  const double beta = material().rayleigh_stiffness;
  // Rotated rest stiffness: diag(R K0_aa R^T)_i = V (mu |g_a|^2 + (lambda + mu) (R g_a)_i^2).
  const double rest_weight = (hyper ? 0.0 : a) + b * beta;
  for (std::size_t e = 0; e < elements_.size(); ++e) {
    const TetElement& el = elements_[e];
    for (int n = 0; n < 4; ++n) {
      const Vec3 g = el.grad.col(n);
      auto d = out.segment<3>(3 * el.nodes[static_cast<std::size_t>(n)]);
      if (rest_weight != 0.0) {
        const Vec3 rg = rotated() ? Vec3(c.rotation[e] * g) : g;
        const LawParams& law = law_of(el);
        d.array() += rest_weight * el.volume *
                     (law.mu * g.squaredNorm() + (law.lambda + law.mu) * rg.array().square());
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
  if (b != 0.0 && material().rayleigh_mass > 0.0) out += (b * material().rayleigh_mass) * mass_diagonal_;
}

const BlockMatrix* TetFem::assemble_system(double a_mass, double b_damping, double c_stiffness, Scratch& s) const {
  if (law().law != FemLaw::linear && law().law != FemLaw::corotational) return nullptr;
  Cache& cc = cache(s);
  BlockMatrix& K = cc.system;
  const double stiffness = c_stiffness + b_damping * material().rayleigh_stiffness;
  const double mass = a_mass + b_damping * material().rayleigh_mass;
  auto start_diagonal = [&](std::size_t i) {
    K.diagonal[i] = (mass * mass_diagonal_.segment<3>(3 * static_cast<Eigen::Index>(i))).asDiagonal();
  };
  // Element block (a, b) of R K0 R^T: lambda r_a r_b^T + mu r_b r_a^T + mu (r_a . r_b) I with
  // r = sqrt(V) R g (the columns of the rotated gradients). Computed from local copies into a
  // local block, so the compiler need not reload anything after each store into the matrix.
  auto add_block = [](double lambda, double mu, const double (&ra)[3], const double (&rb)[3], double* out) {
    double block[9];
    const double diagonal = mu * (ra[0] * rb[0] + ra[1] * rb[1] + ra[2] * rb[2]);
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) block[i + 3 * j] = lambda * ra[i] * rb[j] + mu * rb[i] * ra[j];
    for (int i = 0; i < 3; ++i) block[4 * i] += diagonal;
    for (int k = 0; k < 9; ++k) out[k] += block[k];
  };
  const bool consistent = mass_kind_ == FemMass::consistent && mass != 0.0;
  auto gradients = [&](std::size_t e) { return rotated() ? cc.rotated_grad[e].data() : elements_[e].sgrad.data(); };
  // One region: its constants once, not looked up per block (the row-by-row path visits each
  // element's blocks from several rows).
  const bool one_region = laws_.size() == 1;
  const double lambda_one = stiffness * law().lambda, mu_one = stiffness * law().mu;
  if (thread_count() > 1 && elements_.size() >= 2 * kElementGrain) {
    // Row by row on every thread: each diagonal and upper block gathers its elements' terms
    // in element order, so the sums are the serial loop's, bit for bit.
    // Each block is summed in a local array from zero (or the mass) and stored once.
    parallel_for(0, node_count(), [&](std::size_t begin, std::size_t end) {
      double ra[3], rb[3];
      for (std::size_t i = begin; i < end; ++i) {
        start_diagonal(i);
        double d[9];
        std::copy(K.diagonal[i].data(), K.diagonal[i].data() + 9, d);
        for (auto k = node_start_[i]; k < node_start_[i + 1]; ++k) {
          const auto slot = static_cast<std::size_t>(node_slot_[static_cast<std::size_t>(k)]);
          const double* g = gradients(slot / 4) + 3 * (slot % 4);
          for (int c = 0; c < 3; ++c) ra[c] = g[c];
          const LawParams& law = law_of(elements_[slot / 4]);
          add_block(one_region ? lambda_one : stiffness * law.lambda, one_region ? mu_one : stiffness * law.mu, ra, ra, d);
        }
        std::copy(d, d + 9, K.diagonal[i].data());
        for (auto k = block_row_start_[i]; k < block_row_start_[i + 1]; ++k) {
          double out[9] = {};
          for (auto t = block_pair_start_[static_cast<std::size_t>(k)]; t < block_pair_start_[static_cast<std::size_t>(k) + 1]; ++t) {
            const std::int32_t stored = block_pair_[static_cast<std::size_t>(t)];
            const auto code = static_cast<std::size_t>(stored >= 0 ? stored : -1 - stored);
            const std::size_t e = code / 6, p = code % 6;
            if (consistent) {
              const double m = mass * density_of(elements_[e]) * elements_[e].volume / 20.0;
              for (int c = 0; c < 3; ++c) out[4 * c] += m;
            }
            const double* g = gradients(e);
            for (int c = 0; c < 3; ++c) {
              ra[c] = g[3 * kPairs[p][0] + static_cast<std::size_t>(c)];
              rb[c] = g[3 * kPairs[p][1] + static_cast<std::size_t>(c)];
            }
            const LawParams& law = law_of(elements_[e]);
            const double lambda = one_region ? lambda_one : stiffness * law.lambda;
            const double mu = one_region ? mu_one : stiffness * law.mu;
            if (stored >= 0)
              add_block(lambda, mu, ra, rb, out);
            else
              add_block(lambda, mu, rb, ra, out);
          }
          std::copy(out, out + 9, K.upper[static_cast<std::size_t>(k)].data());
        }
      }
    }, kNodeGrain);
    return &K;
  }
  for (std::size_t i = 0; i < K.diagonal.size(); ++i) start_diagonal(i);
  std::fill(K.upper.begin(), K.upper.end(), Mat3::Zero());
  double r[4][3];
  for (std::size_t e = 0; e < elements_.size(); ++e) {
    const TetElement& el = elements_[e];
    if (consistent) {
      // The consistent mass's off-diagonal blocks rho V/20 I (the diagonal ones are in mass_diagonal_).
      const double m = mass * density_of(el) * el.volume / 20.0;
      for (std::size_t p = 0; p < kPairs.size(); ++p) {
        const std::int32_t index = pair_block_[e][p];
        double* block = K.upper[static_cast<std::size_t>(index >= 0 ? index : -1 - index)].data();
        for (int i = 0; i < 3; ++i) block[4 * i] += m;
      }
    }
    const double* g = gradients(e);  // column a at g + 3 a
    for (int k = 0; k < 12; ++k) r[k / 3][k % 3] = g[k];
    const double lambda = stiffness * law_of(el).lambda, mu = stiffness * law_of(el).mu;
    for (std::size_t n = 0; n < 4; ++n)
      add_block(lambda, mu, r[n], r[n], K.diagonal[static_cast<std::size_t>(el.nodes[n])].data());
    for (std::size_t p = 0; p < kPairs.size(); ++p) {
      const std::int32_t index = pair_block_[e][p];
      const auto& ra = r[kPairs[p][0]];
      const auto& rb = r[kPairs[p][1]];
      // Block (b, a) is the transpose of (a, b): swap the roles where the pair is stored transposed.
      if (index >= 0)
        add_block(lambda, mu, ra, rb, K.upper[static_cast<std::size_t>(index)].data());
      else
        add_block(lambda, mu, rb, ra, K.upper[static_cast<std::size_t>(-1 - index)].data());
    }
  }
  return &K;
}

void TetFem::element_matrix(std::size_t e, double a, double b, const Cache& c, Mat12& k) const {
  // Column by column: the element's response to each unit nodal displacement.
  const TetElement& el = elements_[e];
  const bool hyper = law().law != FemLaw::linear && law().law != FemLaw::corotational;
  const double beta = material().rayleigh_stiffness;
  const Mat3 R = rotated() ? c.rotation[e] : Mat3::Identity();
  for (int col = 0; col < 12; ++col) {
    const int node = col / 3, dir = col % 3;
    Mat3 dF = Mat3::Zero();
    dF.row(dir) = el.grad.col(node).transpose();
    Mat3 S = Mat3::Zero();
    // The linear (rest) stiffness only where it contributes: a hyperelastic tangent without
    // stiffness-proportional damping (static solves) never reads it.
    const LawParams& law = law_of(el);
    auto rest = [&] { return Mat3(R * hooke_of_gradient(law.lambda, law.mu, R.transpose() * dF)); };
    if (hyper) {
      // dF has one nonzero row, so dP = tangent · vec(dF) takes three of the tangent's
      // columns (vec is column-major: entry (dir, m) is dir + 3m).
      const Mat9& A = c.tangent[e];
      Vec9 dP = A.col(dir) * el.grad(0, node);
      dP += A.col(dir + 3) * el.grad(1, node);
      dP += A.col(dir + 6) * el.grad(2, node);
      S += a * Eigen::Map<const Mat3>(dP.data());
      if (b * beta != 0.0) S += (b * beta) * rest();
    } else {
      S += (a + b * beta) * rest();
    }
    S *= el.volume;
    for (int n = 0; n < 4; ++n) k.block<3, 1>(3 * n, col) = S * el.grad.col(n);
  }
}

template <class Emit>
void TetFem::emit_triplets(double a, double b, const Cache& c, Emit&& emit) const {
  Mat12 k;
  for (std::size_t e = 0; e < elements_.size(); ++e) {
    element_matrix(e, a, b, c, k);
    const TetElement& el = elements_[e];
    for (int cn = 0; cn < 4; ++cn)
      for (int rn = 0; rn < 4; ++rn)
        for (int j = 0; j < 3; ++j)
          for (int i = 0; i < 3; ++i)
            emit(3 * el.nodes[static_cast<std::size_t>(rn)] + i, 3 * el.nodes[static_cast<std::size_t>(cn)] + j,
                 k(3 * rn + i, 3 * cn + j));
  }
  if (b != 0.0 && material().rayleigh_mass > 0.0) emit_mass_triplets(b * material().rayleigh_mass, emit);
}

std::size_t TetFem::triplet_count(double b) const {
  return 144 * elements_.size() + (b != 0.0 && material().rayleigh_mass > 0.0 ? mass_triplet_count() : 0);
}

void TetFem::add_triplets(double a, double b, std::vector<Triplet>& out, const Scratch& s) const {
  out.reserve(out.size() + triplet_count(b));
  expand_deferred_tangent(cache(s));
  emit_triplets(a, b, cache(s), [&](Eigen::Index row, Eigen::Index col, double v) { out.emplace_back(row, col, v); });
}

bool TetFem::add_matrix_values(double a, double b, double mass, std::span<const std::int32_t> slots, double* values,
                               const Scratch& s) const {
  if (slots.size() != triplet_count(b) + (mass != 0.0 ? mass_triplet_count() : 0)) return false;
  expand_deferred_tangent(cache(s));
  std::size_t k = 0;
  auto add = [&](Eigen::Index, Eigen::Index, double v) {
    if (slots[k] >= 0) values[slots[k]] += v;
    ++k;
  };
  emit_triplets(a, b, cache(s), add);
  if (mass != 0.0) emit_mass_triplets(mass, add);
  return true;
}

void TetFem::update_internal(const VecX& x, double dt, VecX& q, Scratch& s) const {
  if (q_stride_ == 0 || static_cast<std::size_t>(q.size()) != internal_size()) return;
  Cache& c = cache(s);
  const bool corot = law().law == FemLaw::corotational;
  if (corot) ensure_rotations(x, c);
  parallel_for(0, elements_.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t e = begin; e < end; ++e) {
      const Mat3 F = gradient_of(x, elements_[e]);
      const std::span<double> qe(q.data() + e * q_stride_, q_stride_);
      if (hyperelastic()) {
        // Finite strain (Simo 1987; Holzapfel 2000 §6.10): the branches relax the
        // instantaneous second Piola-Kirchhoff stress S0 = F^-1 P0(F), all of it or its
        // isochoric part Dev S0 = S0 - (S0 : C) C^-1 / 3. The reference frame makes the
        // history objective. A flat or inverted element (J <= 0) has no F^-1: its branches
        // only decay this step.
        const double J = F.determinant();
        if (!(J > 1e-9)) {
          prony_update(material().prony, prony_reference(qe), dt, qe);
          continue;
        }
        Mat3 P;
        hyperelastic_stress_tangent(law_of(elements_[e]), F, P, nullptr);
        const Mat3 F_inv = F.inverse();
        Mat3 S0 = F_inv * P;
        S0 = 0.5 * (S0 + S0.transpose());  // symmetric in exact arithmetic
        if (!material().prony_relaxes_bulk) {
          const Mat3 C = F.transpose() * F;
          const Mat3 C_inv = F_inv * F_inv.transpose();
          S0 -= ((S0.cwiseProduct(C)).sum() / 3.0) * C_inv;
        }
        prony_update(material().prony, S0, dt, qe);
        continue;
      }
      Mat3 grad = corot ? Mat3(c.rotation[e].transpose() * F) : F;
      grad.diagonal().array() -= 1.0;
      const Mat3 eps = 0.5 * (grad + grad.transpose());
      const LawParams& law = law_of(elements_[e]);
      const Mat3 sbar =
          material().prony_relaxes_bulk ? hooke(law.lambda, law.mu, eps) : Mat3(2.0 * law.mu * deviator(eps));
      prony_update(material().prony, sbar, dt, qe);
    }
  }, kElementGrain);
}

double TetFem::elastic_energy(const VecX& x, const VecX&) const {
  double energy = 0.0;
  for (const TetElement& el : elements_) energy += el.volume * strain_energy_density(law_of(el), gradient_of(x, el));
  return energy;
}

}  // namespace tactus::physics
