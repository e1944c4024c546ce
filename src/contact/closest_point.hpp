#pragma once
// Closest points on triangles and on whole triangle surfaces given by current vertex
// positions (the surfaces deform, so the query takes positions, not a mesh copy).
#include <cstdint>
#include <span>
#include <vector>

#include "core/math.hpp"
#include "mesh/tri_mesh.hpp"

namespace tactus::contact {

struct TrianglePoint {
  Vec3 point = Vec3::Zero();
  Vec3 barycentric = Vec3::Zero();  ///< weights of the triangle's vertices a, b, c
};

/// The point of triangle (a, b, c) closest to p (Ericson, Real-Time Collision Detection
/// §5.1.5). Degenerate triangles give a point on their longest edge.
[[nodiscard]] TrianglePoint closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b,
                                                      const Vec3& c);

struct SurfacePoint {
  std::int32_t triangle = -1;       ///< -1 when the surface has no triangles
  Vec3 point = Vec3::Zero();
  Vec3 barycentric = Vec3::Zero();
  Vec3 normal = Vec3::Zero();       ///< unit face normal (outward for an outward mesh)
  double distance = 0.0;            ///< |p − point|
};

/// Closest point of the surface (triangles over `positions`) to p, by visiting every
/// triangle. Ties keep the lowest triangle index, so the answer is deterministic.
[[nodiscard]] SurfacePoint closest_point_on_surface(const Vec3& p, std::span<const Vec3> positions,
                                                    std::span<const mesh::Triangle> triangles);

}  // namespace tactus::contact
