#include "contact/load_spread.hpp"

#include <algorithm>
#include <cmath>

namespace tactus::contact {

std::vector<double> vertex_areas(std::span<const Vec3> positions, std::span<const mesh::Triangle> triangles) {
  std::vector<double> area(positions.size(), 0.0);
  for (const mesh::Triangle& t : triangles) {
    const auto a = static_cast<std::size_t>(t[0]), b = static_cast<std::size_t>(t[1]), c = static_cast<std::size_t>(t[2]);
    if (a >= positions.size() || b >= positions.size() || c >= positions.size()) continue;
    const double third = (positions[b] - positions[a]).cross(positions[c] - positions[a]).norm() / 6.0;
    area[a] += third;
    area[b] += third;
    area[c] += third;
  }
  return area;
}

double sphere_contact_radius(double sphere_radius, double depth) {
  if (!(sphere_radius > 0.0) || !(depth > 0.0)) return 0.0;
  return std::sqrt(sphere_radius * std::min(depth, sphere_radius));
}

int spread_load(std::span<const Vec3> positions, std::span<const mesh::Triangle> triangles,
                std::span<const double> areas, std::int32_t triangle, const Vec3& barycentric,
                double contact_radius, std::span<LoadShare> out) {
  if (out.empty() || triangle < 0 || static_cast<std::size_t>(triangle) >= triangles.size()) return 0;
  const mesh::Triangle& tri = triangles[static_cast<std::size_t>(triangle)];
  for (const mesh::Index v : tri)
    if (v < 0 || static_cast<std::size_t>(v) >= positions.size()) return 0;
  const Vec3& a = positions[static_cast<std::size_t>(tri[0])];
  const Vec3& b = positions[static_cast<std::size_t>(tri[1])];
  const Vec3& c = positions[static_cast<std::size_t>(tri[2])];
  const Vec3 point = barycentric[0] * a + barycentric[1] * b + barycentric[2] * c;
  const double edge = std::sqrt(std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()}));
  const double radius = std::max(std::isfinite(contact_radius) ? contact_radius : 0.0, edge);
  const double r2 = contact_radius < 0.0 ? 0.0 : radius * radius;

  // The nearest vertices within the radius, kept sorted by squared distance (in `share`
  // until the weights are known).
  int count = 0;
  const int capacity = static_cast<int>(out.size());
  const bool with_areas = areas.size() == positions.size();
  for (std::size_t v = 0; v < positions.size(); ++v) {
    const double d2 = (positions[v] - point).squaredNorm();
    if (!(d2 < r2)) continue;
    if (count == capacity && d2 >= out[static_cast<std::size_t>(count - 1)].share) continue;
    int i = count < capacity ? count++ : count - 1;
    for (; i > 0 && out[static_cast<std::size_t>(i - 1)].share > d2; --i) out[static_cast<std::size_t>(i)] = out[static_cast<std::size_t>(i - 1)];
    out[static_cast<std::size_t>(i)] = {static_cast<std::int32_t>(v), d2};
  }
  double total = 0.0;
  for (int i = 0; i < count; ++i) {
    LoadShare& s = out[static_cast<std::size_t>(i)];
    const double area = with_areas ? areas[static_cast<std::size_t>(s.vertex)] : 1.0;
    s.share = area * std::sqrt(std::max(0.0, 1.0 - s.share / r2));
    total += s.share;
  }
  if (!(total > 0.0) || !std::isfinite(total)) {
    // Degenerate (zero-area) surroundings: the triangle's own corners by barycentric weights.
    count = 0;
    for (int k = 0; k < 3 && count < capacity; ++k) out[static_cast<std::size_t>(count++)] = {tri[static_cast<std::size_t>(k)], barycentric[k]};
    return count;
  }
  for (int i = 0; i < count; ++i) out[static_cast<std::size_t>(i)].share /= total;
  return count;
}

}  // namespace tactus::contact
