#include "precompute/interpolator.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace tactus::precompute {

namespace {

constexpr int kPoly = 10;  // quadratic basis in 3D
constexpr int kMax = Interpolator::kStencil + 4;
using Small = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMax, kMax>;
using SmallVec = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMax, 1>;

double phi(Interpolation m, double r) {
  if (m == Interpolation::rbf_cubic) return r * r * r;
  return r > 0.0 ? r * r * std::log(r) : 0.0;
}

/// Quadratic basis at t (grid units, centred on the cell).
Eigen::Matrix<double, kPoly, 1> quadratic(const Vec3& t) {
  Eigen::Matrix<double, kPoly, 1> q;
  q << 1.0, t.x(), t.y(), t.z(), t.x() * t.x(), t.y() * t.y(), t.z() * t.z(), t.x() * t.y(), t.x() * t.z(),
      t.y() * t.z();
  return q;
}

bool is_rbf(Interpolation m) { return m == Interpolation::rbf_cubic || m == Interpolation::rbf_thin_plate; }

}  // namespace

Interpolator::Interpolator(std::shared_ptr<const Space> space, Interpolation method)
    : space_(std::move(space)), method_(method) {
  int n = 0;
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) offsets_[static_cast<std::size_t>(n++)] = {i, j, k};
  for (int a = 0; a < 3; ++a)
    for (int side : {-1, 2})
      for (int u = 0; u < 2; ++u)
        for (int v = 0; v < 2; ++v) {
          std::array<int, 3> o{};
          o[static_cast<std::size_t>(a)] = side;
          o[static_cast<std::size_t>((a + 1) % 3)] = u;
          o[static_cast<std::size_t>((a + 2) % 3)] = v;
          offsets_[static_cast<std::size_t>(n++)] = o;
        }
  // Centres relative to the cell's centre, where queries land.
  auto centre = [&](int i) {
    const auto& o = offsets_[static_cast<std::size_t>(i)];
    return Vec3(o[0] - 0.5, o[1] - 0.5, o[2] - 0.5);
  };
  if (is_rbf(method_)) {
    Eigen::MatrixXd a = Eigen::MatrixXd::Zero(kMax, kMax);
    for (int i = 0; i < kStencil; ++i) {
      for (int j = 0; j < kStencil; ++j) a(i, j) = phi(method_, (centre(i) - centre(j)).norm());
      const Vec3 c = centre(i);
      const double row[4] = {1.0, c.x(), c.y(), c.z()};
      for (int k = 0; k < 4; ++k) a(i, kStencil + k) = a(kStencil + k, i) = row[k];
    }
    full_ = a.fullPivLu().inverse();
  } else if (method_ == Interpolation::polynomial) {
    Eigen::MatrixXd p(kStencil, kPoly);
    for (int i = 0; i < kStencil; ++i) p.row(i) = quadratic(centre(i)).transpose();
    full_ = (p.transpose() * p).ldlt().solve(p.transpose());  // kPoly x kStencil
  }
  if (method_ == Interpolation::trilinear) return;
  // Every partial stencil of the space, once.
  const Grid& g = space_->grid;
  std::array<int, 3> cell{};
  for (cell[2] = 0; cell[2] < std::max(1, g.counts[2] - 1); ++cell[2])
    for (cell[1] = 0; cell[1] < std::max(1, g.counts[1] - 1); ++cell[1])
      for (cell[0] = 0; cell[0] < std::max(1, g.counts[0] - 1); ++cell[0]) {
        std::uint32_t used = 0;
        for (int s = 0; s < kStencil; ++s) {
          const auto& o = offsets_[static_cast<std::size_t>(s)];
          const int i = cell[0] + o[0], j = cell[1] + o[1], k = cell[2] + o[2];
          if (g.contains(i, j, k) && space_->solved(g.index(i, j, k))) used |= 1u << s;
        }
        if (used == 0xffffffffu) continue;
        const auto at = std::lower_bound(partial_.begin(), partial_.end(), used,
                                         [](const auto& e, std::uint32_t m) { return e.first < m; });
        if (at != partial_.end() && at->first == used) continue;
        if (partial_.size() >= kMaxPartial) return;
        partial_.insert(at, {used, partial_matrix(used)});
      }
}

Eigen::MatrixXd Interpolator::partial_matrix(std::uint32_t used) const {
  std::array<Vec3, kStencil> c{};
  int n = 0;
  for (int s = 0; s < kStencil; ++s)
    if (used & (1u << s)) {
      const auto& o = offsets_[static_cast<std::size_t>(s)];
      c[static_cast<std::size_t>(n++)] = Vec3(o[0] - 0.5, o[1] - 0.5, o[2] - 0.5);
    }
  if (is_rbf(method_)) {
    // Rows 0..n-1 of the inverse of the RBF system: weights = rows times the basis vector.
    if (n < 5) return {};
    const int m = n + 4;
    Eigen::MatrixXd a = Eigen::MatrixXd::Zero(m, m);
    for (int r = 0; r < n; ++r) {
      const Vec3& cr = c[static_cast<std::size_t>(r)];
      for (int k = 0; k < n; ++k) a(r, k) = phi(method_, (cr - c[static_cast<std::size_t>(k)]).norm());
      const double row[4] = {1.0, cr.x(), cr.y(), cr.z()};
      for (int k = 0; k < 4; ++k) a(r, n + k) = a(n + k, r) = row[k];
    }
    const Eigen::FullPivLU<Eigen::MatrixXd> lu(a);
    if (!lu.isInvertible()) return {};
    return lu.inverse().topRows(n);
  }
  // Least squares: weight r = q(c_r)^T N^-1 q(x), N = sum q(c_r) q(c_r)^T; rows q(c_r)^T N^-1.
  if (n < kPoly) return {};
  Eigen::MatrixXd q(n, kPoly);
  for (int r = 0; r < n; ++r) q.row(r) = quadratic(c[static_cast<std::size_t>(r)]).transpose();
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(q.transpose() * q);
  if (!lu.isInvertible()) return {};
  return q * lu.inverse();
}

bool Interpolator::trilinear(const std::array<int, 3>& cell, const Vec3& t, Weights& out) const noexcept {
  const Grid& g = space_->grid;
  out.count = 0;
  double sum = 0.0;
  for (int c = 0; c < 8; ++c) {
    const auto& o = offsets_[static_cast<std::size_t>(c)];
    const int i = cell[0] + o[0], j = cell[1] + o[1], k = cell[2] + o[2];
    if (!g.contains(i, j, k)) continue;
    const std::size_t p = g.index(i, j, k);
    if (!space_->solved(p)) continue;
    const double w = (o[0] ? t.x() : 1.0 - t.x()) * (o[1] ? t.y() : 1.0 - t.y()) * (o[2] ? t.z() : 1.0 - t.z());
    out.point[static_cast<std::size_t>(out.count)] = static_cast<std::int64_t>(p);
    out.weight[static_cast<std::size_t>(out.count)] = w;
    ++out.count;
    sum += w;
  }
  if (out.count == 0) return false;
  if (sum > 1e-12) {
    // Missing corners: the solved ones share their weight.
    for (int c = 0; c < out.count; ++c) out.weight[static_cast<std::size_t>(c)] /= sum;
  } else {
    // Only corners of zero weight are solved: take the first of them.
    out.count = 1;
    out.weight[0] = 1.0;
  }
  return true;
}

bool Interpolator::scattered(const std::array<int, 3>& cell, const Vec3& t, Weights& out) const noexcept {
  const Grid& g = space_->grid;
  std::array<int, kStencil> used{};
  std::uint32_t mask = 0;
  int n = 0;
  for (int s = 0; s < kStencil; ++s) {
    const auto& o = offsets_[static_cast<std::size_t>(s)];
    const int i = cell[0] + o[0], j = cell[1] + o[1], k = cell[2] + o[2];
    if (!g.contains(i, j, k)) continue;
    const std::size_t p = g.index(i, j, k);
    if (!space_->solved(p)) continue;
    mask |= 1u << s;
    used[static_cast<std::size_t>(n)] = s;
    out.point[static_cast<std::size_t>(n)] = static_cast<std::int64_t>(p);
    ++n;
  }
  const Vec3 x = t - Vec3::Constant(0.5);
  auto centre = [&](int s) {
    const auto& o = offsets_[static_cast<std::size_t>(s)];
    return Vec3(o[0] - 0.5, o[1] - 0.5, o[2] - 0.5);
  };
  out.count = n;
  if (n == kStencil) {
    // The usual case: the precomputed inverse.
    if (is_rbf(method_)) {
      Eigen::Matrix<double, kMax, 1> b;
      for (int s = 0; s < kStencil; ++s) b[s] = phi(method_, (x - centre(s)).norm());
      b.tail<4>() << 1.0, x.x(), x.y(), x.z();
      for (int s = 0; s < kStencil; ++s) out.weight[static_cast<std::size_t>(s)] = full_.row(s).dot(b);
    } else {
      const auto q = quadratic(x);
      for (int s = 0; s < kStencil; ++s) out.weight[static_cast<std::size_t>(s)] = full_.col(s).dot(q);
    }
    return true;
  }
  // A partial stencil (the grid's border, or unsolved points): its matrix from the table
  // when the constructor met it (every stencil of the space it was given, up to kMaxPartial
  // kinds), else solve the small system here, in fixed-capacity matrices.
  const auto known = std::lower_bound(partial_.begin(), partial_.end(), mask,
                                      [](const auto& e, std::uint32_t m) { return e.first < m; });
  if (known != partial_.end() && known->first == mask) {
    const Eigen::MatrixXd& w = known->second;
    if (w.rows() == 0) return false;  // singular: trilinear instead
    if (is_rbf(method_)) {
      Eigen::Matrix<double, kMax, 1> b;
      for (int r = 0; r < n; ++r) b[r] = phi(method_, (x - centre(used[static_cast<std::size_t>(r)])).norm());
      b.segment<4>(n) << 1.0, x.x(), x.y(), x.z();
      for (int r = 0; r < n; ++r) out.weight[static_cast<std::size_t>(r)] = w.row(r).dot(b.head(n + 4));
    } else {
      const auto q = quadratic(x);
      for (int r = 0; r < n; ++r) out.weight[static_cast<std::size_t>(r)] = w.row(r).dot(q);
    }
    return true;
  }
  if (is_rbf(method_)) {
    if (n < 5) return false;
    const int m = n + 4;
    Small a = Small::Zero(m, m);
    SmallVec b(m);
    for (int r = 0; r < n; ++r) {
      const Vec3 cr = centre(used[static_cast<std::size_t>(r)]);
      for (int c = 0; c < n; ++c) a(r, c) = phi(method_, (cr - centre(used[static_cast<std::size_t>(c)])).norm());
      const double row[4] = {1.0, cr.x(), cr.y(), cr.z()};
      for (int k = 0; k < 4; ++k) a(r, n + k) = a(n + k, r) = row[k];
      b[r] = phi(method_, (x - cr).norm());
    }
    b[n] = 1.0;
    b[n + 1] = x.x();
    b[n + 2] = x.y();
    b[n + 3] = x.z();
    Eigen::FullPivLU<Small> lu(a);
    if (!lu.isInvertible()) return false;
    const SmallVec w = lu.solve(b);
    for (int r = 0; r < n; ++r) out.weight[static_cast<std::size_t>(r)] = w[r];
    return w.allFinite();
  }
  if (n < kPoly) return false;
  Eigen::Matrix<double, kPoly, kPoly> normal = Eigen::Matrix<double, kPoly, kPoly>::Zero();
  for (int r = 0; r < n; ++r) {
    const auto q = quadratic(centre(used[static_cast<std::size_t>(r)]));
    normal.noalias() += q * q.transpose();
  }
  Eigen::FullPivLU<Eigen::Matrix<double, kPoly, kPoly>> lu(normal);
  if (!lu.isInvertible()) return false;
  const Eigen::Matrix<double, kPoly, 1> y = lu.solve(quadratic(x));
  for (int r = 0; r < n; ++r)
    out.weight[static_cast<std::size_t>(r)] = quadratic(centre(used[static_cast<std::size_t>(r)])).dot(y);
  return true;
}

void Interpolator::weights(const Vec3& p, Weights& out) const noexcept {
  const Grid& g = space_->grid;
  std::array<int, 3> cell{};
  Vec3 t;
  for (int a = 0; a < 3; ++a) {
    const auto ua = static_cast<std::size_t>(a);
    double u = (p[a] - g.origin[a]) / g.spacing;
    const double top = g.counts[ua] - 1;
    if (!(u >= 0.0 && u <= top)) {
      out.query.outside = true;
      u = std::isnan(u) ? 0.0 : std::clamp(u, 0.0, top);
    }
    const int c = g.counts[ua] >= 2 ? std::clamp(static_cast<int>(std::floor(u)), 0, g.counts[ua] - 2) : 0;
    cell[ua] = c;
    t[a] = u - c;
  }
  bool ok = false;
  if (method_ != Interpolation::trilinear) ok = scattered(cell, t, out);
  if (!ok) {
    out.query.fallback = method_ != Interpolation::trilinear;
    ok = trilinear(cell, t, out);
  }
  out.query.valid = ok;
  if (!ok) out.count = 0;
}

Query Interpolator::force(const Vec3& p) const noexcept {
  Weights w;
  weights(p, w);
  Vec3 f = Vec3::Zero();
  for (int i = 0; i < w.count; ++i)
    f += w.weight[static_cast<std::size_t>(i)] * space_->force[static_cast<std::size_t>(w.point[static_cast<std::size_t>(i)])];
  w.query.force = f;
  return w.query;
}

Query Interpolator::shape(const Vec3& p, VecX& displacement) const {
  Weights w;
  weights(p, w);
  const auto rows = space_->displacement.rows();
  if (displacement.size() != rows) displacement.resize(rows);
  displacement.setZero();
  Vec3 f = Vec3::Zero();
  for (int i = 0; i < w.count; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const auto point = static_cast<std::size_t>(w.point[k]);
    f += w.weight[k] * space_->force[point];
    displacement.noalias() += w.weight[k] * space_->displacement.col(static_cast<Eigen::Index>(point));
  }
  w.query.force = f;
  return w.query;
}

}  // namespace tactus::precompute
