#pragma once
// Triangle surface mesh as plain arrays; richer topology lives in half_edge.hpp.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "core/math.hpp"

namespace tactus::mesh {

using Index = std::int32_t;
using Triangle = std::array<Index, 3>;
using Tet = std::array<Index, 4>;

/// One key for the undirected edge {a, b}: the same for (a, b) and (b, a).
[[nodiscard]] constexpr std::uint64_t edge_key(Index a, Index b) {
  const auto lo = static_cast<std::uint64_t>(static_cast<std::uint32_t>(a < b ? a : b));
  const auto hi = static_cast<std::uint64_t>(static_cast<std::uint32_t>(a < b ? b : a));
  return (lo << 32) | hi;
}

/// The point at `barycentric` on triangle `corners` of `vertices` (which must hold its corners).
[[nodiscard]] inline Vec3 point_on(std::span<const Vec3> vertices, const Triangle& corners, const Vec3& barycentric) {
  return barycentric[0] * vertices[static_cast<std::size_t>(corners[0])] +
         barycentric[1] * vertices[static_cast<std::size_t>(corners[1])] +
         barycentric[2] * vertices[static_cast<std::size_t>(corners[2])];
}

/// Triangles are counter-clockwise seen from outside (normals point out).
struct TriMesh {
  std::vector<Vec3> vertices;
  std::vector<Triangle> triangles;

  [[nodiscard]] Aabb bounds() const;
  [[nodiscard]] double area() const;
  /// Volume by the divergence theorem; the true volume when the mesh is closed and
  /// outward oriented (negative when inward).
  [[nodiscard]] double signed_volume() const;
  [[nodiscard]] Vec3 face_normal(std::size_t t) const;  ///< unit; zero if degenerate
  [[nodiscard]] double face_area(std::size_t t) const;
  /// FNV-1a over the vertex and triangle bytes: the identity files built from this mesh
  /// (impostor levels, property images) are checked against.
  [[nodiscard]] std::uint64_t content_hash() const;
};

}  // namespace tactus::mesh
