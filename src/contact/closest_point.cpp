#include "contact/closest_point.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace tactus::contact {

TrianglePoint closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  // Voronoi regions of the vertices, then the edges, then the face.
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return {a, Vec3(1, 0, 0)};
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return {b, Vec3(0, 1, 0)};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 && d1 - d3 > 0.0) {
    const double v = d1 / (d1 - d3);
    return {a + v * ab, Vec3(1 - v, v, 0)};
  }
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return {c, Vec3(0, 0, 1)};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 && d2 - d6 > 0.0) {
    const double w = d2 / (d2 - d6);
    return {a + w * ac, Vec3(1 - w, 0, w)};
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 && (d4 - d3) + (d5 - d6) > 0.0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {b + w * (c - b), Vec3(0, 1 - w, w)};
  }
  const double sum = va + vb + vc;
  if (!(sum > 0.0)) {
    // Degenerate (collinear) triangle: the best of its three edges.
    auto on_segment = [&](const Vec3& s, const Vec3& e) {
      const Vec3 d = e - s;
      const double len2 = d.squaredNorm();
      const double u = len2 > 0.0 ? std::clamp((p - s).dot(d) / len2, 0.0, 1.0) : 0.0;
      return std::pair{u, Vec3(s + u * d)};
    };
    const auto [u0, q0] = on_segment(a, b);
    const auto [u1, q1] = on_segment(b, c);
    const auto [u2, q2] = on_segment(c, a);
    const double e0 = (p - q0).squaredNorm(), e1 = (p - q1).squaredNorm(), e2 = (p - q2).squaredNorm();
    if (e0 <= e1 && e0 <= e2) return {q0, Vec3(1 - u0, u0, 0)};
    if (e1 <= e2) return {q1, Vec3(0, 1 - u1, u1)};
    return {q2, Vec3(u2, 0, 1 - u2)};
  }
  const double v = vb / sum, w = vc / sum;
  return {a + v * ab + w * ac, Vec3(1 - v - w, v, w)};
}

SurfacePoint closest_point_on_surface(const Vec3& p, std::span<const Vec3> positions,
                                      std::span<const mesh::Triangle> triangles) {
  SurfacePoint best;
  double best_d2 = std::numeric_limits<double>::infinity();
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const auto& tri = triangles[t];
    const Vec3& a = positions[static_cast<std::size_t>(tri[0])];
    const Vec3& b = positions[static_cast<std::size_t>(tri[1])];
    const Vec3& c = positions[static_cast<std::size_t>(tri[2])];
    const TrianglePoint q = closest_point_on_triangle(p, a, b, c);
    const double d2 = (p - q.point).squaredNorm();
    if (d2 < best_d2) {
      best_d2 = d2;
      best.triangle = static_cast<std::int32_t>(t);
      best.point = q.point;
      best.barycentric = q.barycentric;
    }
  }
  if (best.triangle >= 0) {
    const auto& tri = triangles[static_cast<std::size_t>(best.triangle)];
    const Vec3& a = positions[static_cast<std::size_t>(tri[0])];
    const Vec3 n = (positions[static_cast<std::size_t>(tri[1])] - a)
                       .cross(positions[static_cast<std::size_t>(tri[2])] - a);
    const double len = n.norm();
    best.normal = len > 0.0 ? Vec3(n / len) : Vec3::Zero();
    best.distance = std::sqrt(best_d2);
  }
  return best;
}

}  // namespace tactus::contact
