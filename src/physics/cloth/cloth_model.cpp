#include "physics/cloth/cloth_model.hpp"

#include <algorithm>
#include <numbers>
#include <cmath>
#include <string>

#include "core/error.hpp"
#include "mesh/half_edge.hpp"

namespace tactus::physics {
namespace {

inline Vec3 node(const VecX& x, std::int32_t n) { return x.segment<3>(3 * static_cast<Eigen::Index>(n)); }
inline auto node(VecX& x, std::int32_t n) { return x.segment<3>(3 * static_cast<Eigen::Index>(n)); }

// The warp/weft shear angle stays off ±90°, where asin's slope blows up; no fabric gets there.
constexpr double kMaxShearSine = 0.95;

/// One triangle's linearization: K block (n, m) = a_n a_m P_u + b_n b_m P_v + k_s g_n g_mᵀ,
/// D block (n, m) = a_n a_m d_u ŵ_u ŵ_uᵀ + b_n b_m d_v ŵ_v ŵ_vᵀ + d_s g_n g_mᵀ.
struct TriangleLinear {
  Mat3 pu, pv;
  Vec3 g[3];
  Vec3 wu, wv;
  double ks, du, dv, ds;
};
/// One hinge's: K = k g gᵀ, D = d g gᵀ over its nodes (e0, e1, o0, o1).
struct HingeLinear {
  Vec3 g[4];
  double k, d;
};
/// One yarn bend's: block (n, m) of K is w_n w_m H, of D w_n w_m d·t tᵀ, w = (1, −2, 1), t the
/// direction of a − 2b + c (the damping resists only the change of curvature, not a rotation).
struct YarnLinear {
  Mat3 h;
  Vec3 t;
  double d;
};
constexpr double kYarnWeight[3] = {1.0, -2.0, 1.0};
constexpr int kYarnPairs[3][2] = {{0, 1}, {0, 2}, {1, 2}};

struct ClothScratch final : Scratch {
  std::vector<TriangleLinear> triangles;
  std::vector<HingeLinear> hinges;
  std::vector<YarnLinear> yarns;
  BlockMatrix system;
};

constexpr int kHingePairs[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
constexpr int kTrianglePairs[3][2] = {{0, 1}, {0, 2}, {1, 2}};

/// The dihedral angle θ of a hinge (0 flat, signed) and its gradient over (e0, e1, o0, o1)
/// (Bridson, Marino and Fedkiw 2003). False for a degenerate triangle.
bool hinge_angle(const Vec3& e0, const Vec3& e1, const Vec3& o0, const Vec3& o1, double& theta, Vec3 (&g)[4]) {
  const Vec3 e = e1 - e0;
  const Vec3 n1 = e.cross(o0 - e0), n2 = (o1 - e0).cross(e);
  const double l1 = n1.squaredNorm(), l2 = n2.squaredNorm(), el2 = e.squaredNorm();
  if (!(l1 > 0.0 && l2 > 0.0 && el2 > 0.0)) return false;
  const double el = std::sqrt(el2);
  theta = std::atan2(n1.cross(n2).dot(e) / el, n1.dot(n2));
  g[2] = (-el / l1) * n1;
  g[3] = (-el / l2) * n2;
  g[0] = ((o0 - e1).dot(e) / el2) * g[2] + ((o1 - e1).dot(e) / el2) * g[3];
  g[1] = (-(o0 - e0).dot(e) / el2) * g[2] - ((o1 - e0).dot(e) / el2) * g[3];
  return true;
}

}  // namespace

ClothModel::ClothModel(const ClothMesh& cloth, ClothMaterial material) : material_(std::move(material)) {
  const auto& m = cloth.mesh;
  const auto nodes = m.vertices.size();
  if (cloth.uv.size() != nodes)
    throw InputError("cloth: " + std::to_string(cloth.uv.size()) + " (u, v) coordinates for " + std::to_string(nodes) +
                     " vertices");
  if (m.triangles.empty()) throw InputError("cloth: the mesh has no triangles");
  if (!(material_.areal_density > 0.0 && std::isfinite(material_.areal_density)))
    throw InputError("cloth: the areal density must be positive and finite");
  for (double beta : {material_.stretch_damping, material_.shear_damping, material_.bend_damping})
    if (!(beta >= 0.0 && std::isfinite(beta))) throw InputError("cloth: damping time constants must be finite and >= 0");
  if (!(material_.shear_friction >= 0.0 && std::isfinite(material_.shear_friction)) ||
      !(material_.shear_friction_5 >= 0.0 && std::isfinite(material_.shear_friction_5)))
    throw InputError("cloth: the shear friction must be finite and >= 0");
  if (!(material_.shear_stick_angle > 0.0 && material_.shear_stick_angle < 0.1))
    throw InputError("cloth: the shear stick angle must be in (0, 0.1) rad");
  const mesh::HalfEdgeMesh topology(m);  // rejects non-manifold and inconsistently oriented meshes

  rest_.resize(3 * static_cast<Eigen::Index>(nodes));
  for (std::size_t i = 0; i < nodes; ++i) {
    if (!m.vertices[i].allFinite() || !cloth.uv[i].allFinite())
      throw InputError("cloth: vertex " + std::to_string(i) + " is not finite");
    rest_.segment<3>(3 * static_cast<Eigen::Index>(i)) = m.vertices[i];
  }
  mass_ = VecX::Zero(rest_.size());
  triangles_ = m.triangles;
  rest_triangles_.resize(triangles_.size());
  for (std::size_t t = 0; t < triangles_.size(); ++t) {
    const auto& tri = triangles_[t];
    Eigen::Matrix2d d;
    d.col(0) = cloth.uv[static_cast<std::size_t>(tri[1])] - cloth.uv[static_cast<std::size_t>(tri[0])];
    d.col(1) = cloth.uv[static_cast<std::size_t>(tri[2])] - cloth.uv[static_cast<std::size_t>(tri[0])];
    const double det = d.determinant();
    const double scale = d.col(0).squaredNorm() + d.col(1).squaredNorm();
    if (!(std::abs(det) > 1e-12 * scale)) throw InputError("cloth: triangle " + std::to_string(t) + " has no area in (u, v)");
    const Eigen::Matrix2d inv = d.inverse();
    TriangleRest& r = rest_triangles_[t];
    r.a[0] = -inv(0, 0) - inv(1, 0), r.a[1] = inv(0, 0), r.a[2] = inv(1, 0);
    r.b[0] = -inv(0, 1) - inv(1, 1), r.b[1] = inv(0, 1), r.b[2] = inv(1, 1);
    r.area = 0.5 * std::abs(det);
    for (auto n : tri) mass_.segment<3>(3 * static_cast<Eigen::Index>(n)).array() += material_.areal_density * r.area / 3.0;
  }
  for (std::size_t i = 0; i < nodes; ++i)
    if (!(mass_[3 * static_cast<Eigen::Index>(i)] > 0.0))
      throw InputError("cloth: vertex " + std::to_string(i) + " belongs to no triangle");

  yarns_ = cloth.yarns;
  for (std::size_t y = 0; y < yarns_.size(); ++y) {
    const YarnBend& b = yarns_[y];
    const std::string where = "cloth: yarn bend " + std::to_string(y);
    for (auto n : {b.a, b.b, b.c})
      if (n < 0 || static_cast<std::size_t>(n) >= nodes) throw InputError(where + " names a vertex out of range");
    const Vec2 first = cloth.uv[static_cast<std::size_t>(b.b)] - cloth.uv[static_cast<std::size_t>(b.a)];
    const Vec2 second = cloth.uv[static_cast<std::size_t>(b.c)] - cloth.uv[static_cast<std::size_t>(b.b)];
    const double spacing = first.norm();
    if (!(spacing > 0.0) || (second - first).norm() > 1e-9 * spacing)
      throw InputError(where + " is not straight and evenly spaced in (u, v)");
    if (!(b.area > 0.0 && std::isfinite(b.area))) throw InputError(where + " needs a positive area");
    if (!(b.curvature_scale > 0.0 && std::isfinite(b.curvature_scale)))
      throw InputError(where + " needs a positive curvature scale");
    yarn_curvature_scale_.push_back(spacing * spacing / b.curvature_scale);  // K = |a − 2b + c| over it
  }
  // Without yarn lines, one hinge per interior edge, from its half-edge whose origin is the
  // smaller vertex.
  for (mesh::Index h = 0; yarns_.empty() && h < static_cast<mesh::Index>(topology.num_half_edges()); ++h) {
    const mesh::Index t = topology.twin(h);
    if (topology.is_boundary(h) || topology.is_boundary(t) || h > t) continue;
    ClothHinge hinge;
    hinge.e0 = topology.origin(h);
    hinge.e1 = topology.target(h);
    hinge.o0 = topology.target(topology.next(h));
    hinge.o1 = topology.target(topology.next(t));
    const auto f0 = static_cast<std::size_t>(topology.face(h)), f1 = static_cast<std::size_t>(topology.face(t));
    const Vec2 edge = cloth.uv[static_cast<std::size_t>(hinge.e1)] - cloth.uv[static_cast<std::size_t>(hinge.e0)];
    const double length = edge.norm();
    hinge.area = rest_triangles_[f0].area + rest_triangles_[f1].area;
    hinge.mean_height = hinge.area / length;  // (2A0/|e| + 2A1/|e|) / 2
    hinge.warp_share = edge.y() * edge.y() / edge.squaredNorm();
    double theta = 0.0;
    Vec3 g[4];
    if (hinge_angle(node(rest_, hinge.e0), node(rest_, hinge.e1), node(rest_, hinge.o0), node(rest_, hinge.o1), theta, g))
      hinge.rest_curvature = 2.0 * std::sin(0.5 * theta) / hinge.mean_height;
    hinges_.push_back(hinge);
  }

  // Block pattern of the assembled system.
  std::vector<std::vector<std::int32_t>> upper(nodes);
  auto link = [&](std::int32_t i, std::int32_t j) { upper[static_cast<std::size_t>(std::min(i, j))].push_back(std::max(i, j)); };
  for (const auto& tri : triangles_)
    for (const auto& p : kTrianglePairs) link(tri[static_cast<std::size_t>(p[0])], tri[static_cast<std::size_t>(p[1])]);
  for (const auto& h : hinges_) link(h.o0, h.o1);  // the other hinge pairs are triangle pairs
  for (const auto& y : yarns_) {
    link(y.a, y.b);
    link(y.a, y.c);
    link(y.b, y.c);
  }
  row_start_.assign(nodes + 1, 0);
  for (std::size_t i = 0; i < nodes; ++i) {
    auto& row = upper[i];
    std::sort(row.begin(), row.end());
    row.erase(std::unique(row.begin(), row.end()), row.end());
    row_start_[i + 1] = row_start_[i] + static_cast<std::int32_t>(row.size());
    column_.insert(column_.end(), row.begin(), row.end());
  }
  auto slot = [&](std::int32_t i, std::int32_t j) {
    const auto lo = static_cast<std::size_t>(std::min(i, j));
    const auto begin = column_.begin() + row_start_[lo], end = column_.begin() + row_start_[lo + 1];
    const auto k = static_cast<std::int32_t>(std::lower_bound(begin, end, std::max(i, j)) - column_.begin());
    return i < j ? k : -1 - k;
  };
  for (const auto& tri : triangles_)
    for (const auto& p : kTrianglePairs)
      triangle_slot_.push_back(slot(tri[static_cast<std::size_t>(p[0])], tri[static_cast<std::size_t>(p[1])]));
  for (const auto& h : hinges_) {
    const std::int32_t n[4] = {h.e0, h.e1, h.o0, h.o1};
    for (const auto& p : kHingePairs) hinge_slot_.push_back(slot(n[p[0]], n[p[1]]));
  }
  for (const auto& y : yarns_) {
    const std::int32_t n[3] = {y.a, y.b, y.c};
    for (const auto& p : kYarnPairs) yarn_slot_.push_back(slot(n[p[0]], n[p[1]]));
  }
}

std::unique_ptr<Scratch> ClothModel::make_scratch() const {
  auto s = std::make_unique<ClothScratch>();
  s->triangles.resize(triangles_.size());
  s->hinges.resize(hinges_.size());
  s->yarns.resize(yarns_.size());
  const auto nodes = node_count();
  s->system.diagonal.resize(nodes);
  s->system.row_start = row_start_;
  s->system.column = column_;
  // The stiff stretch takes CG tens of iterations a step (13–37 on the 20 cm sheet at 5 mm,
  // against about 2 for the tissue meshes the size rule was measured on), so splitting the
  // sweeps pays from half the rule's size: 2.75 against 4.0 ms a 10 ms step on 1,681 nodes
  // (docs/BENCHMARKS.md, cloth global step).
  if (nodes >= 1024 && nodes < 2048) s->system.sweep_ranges = 2;
  s->system.upper.resize(column_.size());
  return s;
}

std::pair<Vec3, Vec3> ClothModel::warp_weft(const VecX& x, std::size_t t) const {
  const auto& tri = triangles_[t];
  const auto& r = rest_triangles_[t];
  Vec3 wu = Vec3::Zero(), wv = Vec3::Zero();
  for (int n = 0; n < 3; ++n) {
    const Vec3 p = node(x, tri[static_cast<std::size_t>(n)]);
    wu += r.a[n] * p;
    wv += r.b[n] * p;
  }
  return {wu, wv};
}

Vec3 ClothModel::triangle_strain(const VecX& x, std::size_t t) const {
  const auto [wu, wv] = warp_weft(x, t);
  const double s = std::clamp(wu.normalized().dot(wv.normalized()), -kMaxShearSine, kMaxShearSine);
  return {wu.norm() - 1.0, wv.norm() - 1.0, std::asin(s)};
}

double ClothModel::hinge_curvature(const VecX& x, std::size_t h) const {
  const ClothHinge& hinge = hinges_[h];
  double theta = 0.0;
  Vec3 g[4];
  if (!hinge_angle(node(x, hinge.e0), node(x, hinge.e1), node(x, hinge.o0), node(x, hinge.o1), theta, g)) return 0.0;
  return 2.0 * std::sin(0.5 * theta) / hinge.mean_height;
}

double ClothModel::yarn_curvature(const VecX& x, std::size_t y) const {
  const YarnBend& b = yarns_[y];
  return (node(x, b.a) - 2.0 * node(x, b.b) + node(x, b.c)).norm() / yarn_curvature_scale_[y];
}

template <bool Linearize>
void ClothModel::evaluate(const VecX& x, const VecX& v, const VecX& q, VecX* f, Scratch& s) const {
  auto& cs = static_cast<ClothScratch&>(s);
  if (f) f->setZero(rest_.size());
  const bool damped = f && v.size() == rest_.size();
  const auto& mat = material_;
  for (std::size_t t = 0; t < triangles_.size(); ++t) {
    const auto& tri = triangles_[t];
    const auto& r = rest_triangles_[t];
    auto [wu, wv] = warp_weft(x, t);
    const double lu = wu.norm(), lv = wv.norm();
    if (!(lu > 0.0 && lv > 0.0)) continue;  // collapsed to a line: no direction to push along
    wu /= lu;
    wv /= lv;
    const double eu = lu - 1.0, ev = lv - 1.0;
    const double sn = std::clamp(wu.dot(wv), -kMaxShearSine, kMaxShearSine);
    const double c = 1.0 / std::sqrt(1.0 - sn * sn);
    const double gamma = std::asin(sn);
    const Vec3 pu = (wv - sn * wu) / lu, pv = (wu - sn * wv) / lv;
    Vec3 g[3];
    for (int n = 0; n < 3; ++n) g[n] = c * (r.a[n] * pu + r.b[n] * pv);
    const double ku = mat.warp.slope(eu), kv = mat.weft.slope(ev), ks = mat.shear.slope(gamma);
    // The shear friction: its force, and its stiffness while it sticks.
    double friction = 0.0, friction_stiffness = 0.0;
    if (mat.shear_friction > 0.0) {
      const double slip = gamma - stick_angle(q, t);
      friction = shear_friction_force(gamma, stick_angle(q, t));
      if (std::abs(slip) < mat.shear_stick_angle)
        friction_stiffness = shear_friction_limit(stick_angle(q, t)) / mat.shear_stick_angle;
    }
    // The tensions, looked up once for the force and the linearization alike.
    const double tu = mat.warp.value(eu), tv = mat.weft.value(ev);
    if (f) {
      const double ts = mat.shear.value(gamma);
      double rate_u = 0.0, rate_v = 0.0, rate_s = 0.0;
      if (damped) {
        for (int n = 0; n < 3; ++n) {
          const Vec3 vn = node(v, tri[static_cast<std::size_t>(n)]);
          rate_u += r.a[n] * wu.dot(vn);
          rate_v += r.b[n] * wv.dot(vn);
          rate_s += g[n].dot(vn);
        }
      }
      const double su = r.area * (tu + mat.stretch_damping * ku * rate_u);
      const double sv = r.area * (tv + mat.stretch_damping * kv * rate_v);
      const double ss = r.area * (ts + friction + mat.shear_damping * ks * rate_s);
      for (int n = 0; n < 3; ++n) node(*f, tri[static_cast<std::size_t>(n)]) -= su * r.a[n] * wu + sv * r.b[n] * wv + ss * g[n];
    }
    if constexpr (Linearize) {
      TriangleLinear& l = cs.triangles[t];
      // Compressed directions keep only their axial stiffness: the transverse term T/l of a
      // compressed fibre is negative and would make K indefinite.
      const double pull_u = std::max(tu, 0.0), pull_v = std::max(tv, 0.0);
      const Mat3 uu = wu * wu.transpose(), vv = wv * wv.transpose();
      l.pu = r.area * (ku * uu + (pull_u / lu) * (Mat3::Identity() - uu));
      l.pv = r.area * (kv * vv + (pull_v / lv) * (Mat3::Identity() - vv));
      for (int n = 0; n < 3; ++n) l.g[n] = g[n];
      l.wu = wu;
      l.wv = wv;
      l.ks = r.area * (ks + friction_stiffness);
      l.du = r.area * mat.stretch_damping * ku;
      l.dv = r.area * mat.stretch_damping * kv;
      l.ds = r.area * mat.shear_damping * ks;
    }
  }
  for (std::size_t h = 0; h < hinges_.size(); ++h) {
    const ClothHinge& hinge = hinges_[h];
    const std::int32_t nodes[4] = {hinge.e0, hinge.e1, hinge.o0, hinge.o1};
    double theta = 0.0;
    Vec3 g[4];
    if (!hinge_angle(node(x, hinge.e0), node(x, hinge.e1), node(x, hinge.o0), node(x, hinge.o1), theta, g)) {
      if constexpr (Linearize) cs.hinges[h] = HingeLinear{{Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()}, 0.0, 0.0};
      continue;
    }
    const double kappa = 2.0 * std::sin(0.5 * theta) / hinge.mean_height - hinge.rest_curvature;
    const double dk = std::cos(0.5 * theta) / hinge.mean_height;  // dK/dθ
    const double w = hinge.warp_share;
    const double slope = w * mat.bend_warp.slope(kappa) + (1.0 - w) * mat.bend_weft.slope(kappa);
    const double k = hinge.area * slope * dk * dk;
    if (f) {
      const double moment = w * mat.bend_warp.value(kappa) + (1.0 - w) * mat.bend_weft.value(kappa);
      double rate = 0.0;
      if (damped)
        for (int n = 0; n < 4; ++n) rate += g[n].dot(node(v, nodes[n]));
      const double scale = hinge.area * moment * dk + mat.bend_damping * k * rate;
      for (int n = 0; n < 4; ++n) node(*f, nodes[n]) -= scale * g[n];
    }
    if constexpr (Linearize) {
      HingeLinear& l = cs.hinges[h];
      for (int n = 0; n < 4; ++n) l.g[n] = g[n];
      l.k = k;
      l.d = mat.bend_damping * k;
    }
  }
  for (std::size_t y = 0; y < yarns_.size(); ++y) {
    // E = A·Φ(K), K = |d|/σ², d = a − 2b + c: ∇E = A·M(K)/(K σ⁴)·d ⊗ (1, −2, 1), and the
    // Hessian A/σ⁴·[M'(K) d̂d̂ᵀ + M(K)/K (I − d̂d̂ᵀ)] ⊗ w wᵀ is exact (d is linear in x).
    const YarnBend& b = yarns_[y];
    const MeasuredCurve& curve = b.warp ? mat.bend_warp : mat.bend_weft;
    const double s2 = yarn_curvature_scale_[y];
    const Vec3 d = node(x, b.a) - 2.0 * node(x, b.b) + node(x, b.c);
    const double len = d.norm(), kappa = len / s2;
    const double slope = curve.slope(kappa);
    const double secant = kappa > 0.0 ? curve.value(kappa) / kappa : slope;  // M/K, M'(0) at K = 0
    const double scale = b.area / (s2 * s2);
    const Vec3 dir = len > 0.0 ? Vec3(d / len) : Vec3::Zero();
    const double damping = mat.bend_damping * scale * slope;
    if (f) {
      Vec3 push = (scale * secant) * d;  // ∂E/∂d
      if (damped) push += (damping * dir.dot(node(v, b.a) - 2.0 * node(v, b.b) + node(v, b.c))) * dir;
      node(*f, b.a) -= push;
      node(*f, b.b) += 2.0 * push;
      node(*f, b.c) -= push;
    }
    if constexpr (Linearize) {
      const Mat3 h = (scale * secant) * Mat3::Identity() + (scale * (slope - secant)) * (dir * dir.transpose());
      cs.yarns[y] = YarnLinear{h, dir, damping};
    }
  }
}

void ClothModel::forces(const VecX& x, const VecX& v, const VecX& q, VecX& f, Scratch& s) const {
  evaluate<false>(x, v, q, &f, s);
}

void ClothModel::linearize(const VecX& x, const VecX& v, const VecX& q, Scratch& s) const {
  evaluate<true>(x, v, q, nullptr, s);
}

void ClothModel::linearized_forces(const VecX& x, const VecX& v, const VecX& q, const VecX& dx, VecX& f,
                                   Scratch& s) const {
  evaluate<true>(x, v, q, &f, s);
  add_stiffness_product(dx, f, s);
}

namespace {

/// out += (c·K + b·D) in, over the yarn bends, triangles and hinges of a linearization.
void add_product(const std::vector<TriangleLinear>& triangles, const std::vector<mesh::Triangle>& tris,
                 const std::vector<ClothModel::TriangleRest>& rest,
                 const std::vector<ClothHinge>& hinges, const std::vector<HingeLinear>& hl,
                 const std::vector<YarnBend>& yarns, const std::vector<YarnLinear>& yl, double c, double b,
                 const VecX& in, VecX& out) {
  for (std::size_t y = 0; y < yarns.size(); ++y) {
    const YarnLinear& l = yl[y];
    const Vec3 d = node(in, yarns[y].a) - 2.0 * node(in, yarns[y].b) + node(in, yarns[y].c);
    const Vec3 push = c * (l.h * d) + (b * l.d * l.t.dot(d)) * l.t;
    node(out, yarns[y].a) += push;
    node(out, yarns[y].b) -= 2.0 * push;
    node(out, yarns[y].c) += push;
  }
  for (std::size_t t = 0; t < tris.size(); ++t) {
    const TriangleLinear& l = triangles[t];
    const auto& r = rest[t];
    Vec3 su = Vec3::Zero(), sv = Vec3::Zero();
    double gs = 0.0;
    for (int n = 0; n < 3; ++n) {
      const Vec3 p = node(in, tris[t][static_cast<std::size_t>(n)]);
      su += r.a[n] * p;
      sv += r.b[n] * p;
      gs += l.g[n].dot(p);
    }
    const Vec3 fu = c * (l.pu * su) + (b * l.du * l.wu.dot(su)) * l.wu;
    const Vec3 fv = c * (l.pv * sv) + (b * l.dv * l.wv.dot(sv)) * l.wv;
    const double fs = (c * l.ks + b * l.ds) * gs;
    for (int n = 0; n < 3; ++n) node(out, tris[t][static_cast<std::size_t>(n)]) += r.a[n] * fu + r.b[n] * fv + fs * l.g[n];
  }
  for (std::size_t h = 0; h < hinges.size(); ++h) {
    const HingeLinear& l = hl[h];
    const std::int32_t nodes[4] = {hinges[h].e0, hinges[h].e1, hinges[h].o0, hinges[h].o1};
    double gs = 0.0;
    for (int n = 0; n < 4; ++n) gs += l.g[n].dot(node(in, nodes[n]));
    const double scale = (c * l.k + b * l.d) * gs;
    for (int n = 0; n < 4; ++n) node(out, nodes[n]) += scale * l.g[n];
  }
}

}  // namespace

void ClothModel::add_stiffness_product(const VecX& dx, VecX& out, const Scratch& s) const {
  const auto& cs = static_cast<const ClothScratch&>(s);
  add_product(cs.triangles, triangles_, rest_triangles_, hinges_, cs.hinges, yarns_, cs.yarns, 1.0, 0.0, dx, out);
}

void ClothModel::add_damping_product(const VecX& dv, VecX& out, const Scratch& s) const {
  const auto& cs = static_cast<const ClothScratch&>(s);
  add_product(cs.triangles, triangles_, rest_triangles_, hinges_, cs.hinges, yarns_, cs.yarns, 0.0, 1.0, dv, out);
}

namespace {

/// Block (n, m) of c·K + b·D of a triangle.
Mat3 triangle_block(const TriangleLinear& l, const ClothModel::TriangleRest& r, int n, int m, double c, double b) {
  const double aa = r.a[n] * r.a[m], bb = r.b[n] * r.b[m];
  return c * (aa * l.pu + bb * l.pv + l.ks * l.g[n] * l.g[m].transpose()) +
         b * (aa * l.du * l.wu * l.wu.transpose() + bb * l.dv * l.wv * l.wv.transpose() + l.ds * l.g[n] * l.g[m].transpose());
}

}  // namespace

void ClothModel::add_diagonal(double a, double b, VecX& out, const Scratch& s) const {
  const auto& cs = static_cast<const ClothScratch&>(s);
  for (std::size_t t = 0; t < triangles_.size(); ++t)
    for (int n = 0; n < 3; ++n)
      node(out, triangles_[t][static_cast<std::size_t>(n)]) +=
          triangle_block(cs.triangles[t], rest_triangles_[t], n, n, a, b).diagonal();
  for (std::size_t h = 0; h < hinges_.size(); ++h) {
    const HingeLinear& l = cs.hinges[h];
    const std::int32_t nodes[4] = {hinges_[h].e0, hinges_[h].e1, hinges_[h].o0, hinges_[h].o1};
    for (int n = 0; n < 4; ++n) node(out, nodes[n]) += (a * l.k + b * l.d) * l.g[n].cwiseAbs2();
  }
  for (std::size_t y = 0; y < yarns_.size(); ++y) {
    const YarnLinear& l = cs.yarns[y];
    const Vec3 diagonal = a * l.h.diagonal() + (b * l.d) * l.t.cwiseAbs2();
    node(out, yarns_[y].a) += diagonal;
    node(out, yarns_[y].b) += 4.0 * diagonal;
    node(out, yarns_[y].c) += diagonal;
  }
}

const BlockMatrix* ClothModel::assemble_system(double a, double b, double c, Scratch& s) const {
  auto& cs = static_cast<ClothScratch&>(s);
  BlockMatrix& A = cs.system;
  for (std::size_t i = 0; i < A.diagonal.size(); ++i) A.diagonal[i] = (a * mass_[3 * static_cast<Eigen::Index>(i)]) * Mat3::Identity();
  std::fill(A.upper.begin(), A.upper.end(), Mat3::Zero());
  auto add = [&A](std::int32_t slot, const Mat3& block) {
    if (slot >= 0)
      A.upper[static_cast<std::size_t>(slot)] += block;
    else
      A.upper[static_cast<std::size_t>(-1 - slot)] += block.transpose();
  };
  for (std::size_t t = 0; t < triangles_.size(); ++t) {
    const auto& tri = triangles_[t];
    for (int n = 0; n < 3; ++n)
      A.diagonal[static_cast<std::size_t>(tri[static_cast<std::size_t>(n)])] +=
          triangle_block(cs.triangles[t], rest_triangles_[t], n, n, c, b);
    for (int p = 0; p < 3; ++p)
      add(triangle_slot_[3 * t + static_cast<std::size_t>(p)],
          triangle_block(cs.triangles[t], rest_triangles_[t], kTrianglePairs[p][0], kTrianglePairs[p][1], c, b));
  }
  for (std::size_t h = 0; h < hinges_.size(); ++h) {
    const HingeLinear& l = cs.hinges[h];
    const double w = c * l.k + b * l.d;
    if (w == 0.0) continue;
    const std::int32_t nodes[4] = {hinges_[h].e0, hinges_[h].e1, hinges_[h].o0, hinges_[h].o1};
    for (int n = 0; n < 4; ++n) A.diagonal[static_cast<std::size_t>(nodes[n])] += w * l.g[n] * l.g[n].transpose();
    for (int p = 0; p < 6; ++p)
      add(hinge_slot_[6 * h + static_cast<std::size_t>(p)], w * l.g[kHingePairs[p][0]] * l.g[kHingePairs[p][1]].transpose());
  }
  for (std::size_t y = 0; y < yarns_.size(); ++y) {
    const YarnLinear& l = cs.yarns[y];
    const Mat3 h = c * l.h + (b * l.d) * (l.t * l.t.transpose());
    const std::int32_t nodes[3] = {yarns_[y].a, yarns_[y].b, yarns_[y].c};
    for (int n = 0; n < 3; ++n) A.diagonal[static_cast<std::size_t>(nodes[n])] += (kYarnWeight[n] * kYarnWeight[n]) * h;
    for (int p = 0; p < 3; ++p)
      add(yarn_slot_[3 * y + static_cast<std::size_t>(p)], (kYarnWeight[kYarnPairs[p][0]] * kYarnWeight[kYarnPairs[p][1]]) * h);
  }
  return &A;
}

template <class Emit>
void ClothModel::emit_blocks(double a, double b, const Scratch& s, Emit&& emit) const {
  const auto& cs = static_cast<const ClothScratch&>(s);
  for (std::size_t t = 0; t < triangles_.size(); ++t)
    for (int n = 0; n < 3; ++n)
      for (int m = 0; m < 3; ++m)
        emit(triangles_[t][static_cast<std::size_t>(n)], triangles_[t][static_cast<std::size_t>(m)],
             triangle_block(cs.triangles[t], rest_triangles_[t], n, m, a, b));
  for (std::size_t h = 0; h < hinges_.size(); ++h) {
    const HingeLinear& l = cs.hinges[h];
    const double w = a * l.k + b * l.d;
    const std::int32_t nodes[4] = {hinges_[h].e0, hinges_[h].e1, hinges_[h].o0, hinges_[h].o1};
    for (int n = 0; n < 4; ++n)
      for (int m = 0; m < 4; ++m) emit(nodes[n], nodes[m], Mat3(w * l.g[n] * l.g[m].transpose()));
  }
  for (std::size_t y = 0; y < yarns_.size(); ++y) {
    const YarnLinear& l = cs.yarns[y];
    const Mat3 h = a * l.h + (b * l.d) * (l.t * l.t.transpose());
    const std::int32_t nodes[3] = {yarns_[y].a, yarns_[y].b, yarns_[y].c};
    for (int n = 0; n < 3; ++n)
      for (int m = 0; m < 3; ++m) emit(nodes[n], nodes[m], Mat3((kYarnWeight[n] * kYarnWeight[m]) * h));
  }
}

void ClothModel::add_triplets(double a, double b, std::vector<Triplet>& out, const Scratch& s) const {
  emit_blocks(a, b, s, [&out](std::int32_t i, std::int32_t j, const Mat3& block) {
    for (int r = 0; r < 3; ++r)
      for (int q = 0; q < 3; ++q) out.emplace_back(3 * i + r, 3 * j + q, block(r, q));
  });
}

bool ClothModel::add_matrix_values(double a, double b, double mass, std::span<const std::int32_t> slots,
                                   double* values, const Scratch& s) const {
  const std::size_t blocks = 9 * triangles_.size() + 16 * hinges_.size() + 9 * yarns_.size();
  if (slots.size() != 9 * blocks + (mass != 0.0 ? static_cast<std::size_t>(mass_.size()) : 0)) return false;
  std::size_t k = 0;
  auto add = [&](double v) {
    if (slots[k] >= 0) values[slots[k]] += v;
    ++k;
  };
  emit_blocks(a, b, s, [&](std::int32_t, std::int32_t, const Mat3& block) {
    for (int r = 0; r < 3; ++r)
      for (int q = 0; q < 3; ++q) add(block(r, q));
  });
  // The lumped mass, as ForceModel::add_mass_triplets appends it.
  if (mass != 0.0)
    for (Eigen::Index i = 0; i < mass_.size(); ++i) add(mass * mass_[i]);
  return true;
}

double ClothModel::shear_friction_limit(double stick) const {
  const double at_half = material_.shear_friction;
  if (!(material_.shear_friction_5 > 0.0)) return at_half;
  constexpr double deg = std::numbers::pi / 180.0;
  const double slope = (material_.shear_friction_5 - at_half) / (4.5 * deg);
  return std::max(0.0, at_half + slope * (std::abs(stick) - 0.5 * deg));
}

double ClothModel::shear_friction_force(double gamma, double stick) const {
  const double limit = shear_friction_limit(stick);
  return std::clamp(limit / material_.shear_stick_angle * (gamma - stick), -limit, limit);
}

void ClothModel::update_internal(const VecX& x, double, VecX& q, Scratch&) const {
  if (internal_size() == 0 || static_cast<std::size_t>(q.size()) != internal_size()) return;
  const double reach = material_.shear_stick_angle;
  for (std::size_t t = 0; t < triangles_.size(); ++t) {
    const double gamma = triangle_strain(x, t)[2];
    double& stick = q[static_cast<Eigen::Index>(t)];
    stick = gamma - std::clamp(gamma - stick, -reach, reach);
  }
}

double ClothModel::elastic_energy(const VecX& x, const VecX& q) const {
  double energy = 0.0;
  const double reach = material_.shear_stick_angle;
  for (std::size_t t = 0; t < triangles_.size(); ++t) {
    const Vec3 e = triangle_strain(x, t);
    double friction = 0.0;
    if (material_.shear_friction > 0.0) {
      const double limit = shear_friction_limit(stick_angle(q, t));
      const double slip = std::abs(e[2] - stick_angle(q, t));
      friction = slip <= reach ? 0.5 * limit / reach * slip * slip : limit * (slip - 0.5 * reach);
    }
    energy += rest_triangles_[t].area * (material_.warp.integral(e[0]) + material_.weft.integral(e[1]) +
                                         material_.shear.integral(e[2]) + friction);
  }
  for (std::size_t h = 0; h < hinges_.size(); ++h) {
    const ClothHinge& hinge = hinges_[h];
    const double kappa = hinge_curvature(x, h) - hinge.rest_curvature;
    energy += hinge.area * (hinge.warp_share * material_.bend_warp.integral(kappa) +
                            (1.0 - hinge.warp_share) * material_.bend_weft.integral(kappa));
  }
  for (std::size_t y = 0; y < yarns_.size(); ++y)
    energy += yarns_[y].area * (yarns_[y].warp ? material_.bend_warp : material_.bend_weft).integral(yarn_curvature(x, y));
  return energy;
}

}  // namespace tactus::physics
