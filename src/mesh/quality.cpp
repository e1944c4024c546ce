#include "mesh/quality.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace tactus::mesh {
namespace {

constexpr double kDeg = 180.0 / std::numbers::pi;

double angle(const Vec3& u, const Vec3& v) { return std::atan2(u.cross(v).norm(), u.dot(v)); }

}  // namespace

void Stats::add(double x) {
  min = std::min(min, x);
  max = std::max(max, x);
  ++count;
  mean += (x - mean) / static_cast<double>(count);
}

TriangleShape triangle_shape(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double min_angle = std::min({angle(b - a, c - a), angle(c - b, a - b), angle(a - c, b - c)});
  const double longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
  const double area = 0.5 * (b - a).cross(c - a).norm();
  // Shortest altitude = 2·area / longest edge.
  const double aspect = area > 0.0 ? longest * longest * std::sqrt(3.0) / (4.0 * area)
                                   : std::numeric_limits<double>::infinity();
  return {min_angle * kDeg, aspect};
}

TetShape tet_shape(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const std::array<Vec3, 4> p{a, b, c, d};
  const double volume = signed_tet_volume(a, b, c, d);

  // Outward face normals (face i opposite vertex i) for the dihedral angles.
  std::array<Vec3, 4> n;
  double face_area_sum = 0.0;
  for (int i = 0; i < 4; ++i) {
    const Vec3& q0 = p[(i + 1) % 4];
    const Vec3& q1 = p[(i + 2) % 4];
    const Vec3& q2 = p[(i + 3) % 4];
    Vec3 m = (q1 - q0).cross(q2 - q0);
    face_area_sum += 0.5 * m.norm();
    if (m.dot(p[i] - q0) > 0.0) m = -m;  // point away from the opposite vertex
    const double len = m.norm();
    n[i] = len > 0.0 ? Vec3(m / len) : Vec3::Zero();
  }
  double min_dihedral = std::numbers::pi, max_dihedral = 0.0;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) {
      const double dihedral = std::numbers::pi - std::acos(std::clamp(n[i].dot(n[j]), -1.0, 1.0));
      min_dihedral = std::min(min_dihedral, dihedral);
      max_dihedral = std::max(max_dihedral, dihedral);
    }

  // Circumradius: |a²(b×c) + b²(c×a) + c²(a×b)| / (12 V) with edge vectors from p0.
  const Vec3 u = b - a, v = c - a, w = d - a;
  const Vec3 num = u.squaredNorm() * v.cross(w) + v.squaredNorm() * w.cross(u) + w.squaredNorm() * u.cross(v);
  double ratio = 0.0;
  if (volume != 0.0 && face_area_sum > 0.0) {
    const double r_in = 3.0 * std::abs(volume) / face_area_sum;
    const double r_circ = num.norm() / (12.0 * std::abs(volume));
    ratio = std::copysign(3.0 * r_in / r_circ, volume);
  }

  double shortest = std::numeric_limits<double>::infinity(), longest = 0.0;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) {
      const double len = (p[i] - p[j]).norm();
      shortest = std::min(shortest, len);
      longest = std::max(longest, len);
    }
  const double edge_ratio = shortest > 0.0 ? longest / shortest : std::numeric_limits<double>::infinity();
  return {ratio, min_dihedral * kDeg, max_dihedral * kDeg, edge_ratio};
}

TriQuality tri_quality(const TriMesh& mesh) {
  TriQuality q;
  for (const auto& f : mesh.triangles) {
    const Vec3 &a = mesh.vertices[f[0]], &b = mesh.vertices[f[1]], &c = mesh.vertices[f[2]];
    const TriangleShape s = triangle_shape(a, b, c);
    q.min_angle_deg.add(s.min_angle_deg);
    q.aspect_ratio.add(s.aspect_ratio);
    q.edge_length.add((b - a).norm());
    q.edge_length.add((c - b).norm());
    q.edge_length.add((a - c).norm());
  }
  return q;
}

TetQuality tet_quality(const TetMesh& mesh) {
  TetQuality q;
  for (const Tet& e : mesh.tets) {
    const TetShape s = tet_shape(mesh.vertices[e[0]], mesh.vertices[e[1]], mesh.vertices[e[2]], mesh.vertices[e[3]]);
    q.radius_ratio.add(s.radius_ratio);
    q.min_dihedral_deg.add(s.min_dihedral_deg);
    q.max_dihedral_deg.add(s.max_dihedral_deg);
    q.edge_length_ratio.add(s.edge_length_ratio);
    if (s.radius_ratio < 0.0) ++q.inverted;
    if (std::abs(s.radius_ratio) < kSliverRadiusRatio) ++q.slivers;
  }
  return q;
}

}  // namespace tactus::mesh
