#pragma once
// The two questions a proxy asks of a surface: where is its closest point (and on which
// side am I), and when does a sphere moving along a segment first touch it. Proxies are
// written against the SurfaceQuery interface so that a brute-force scan (here, for tests
// and small meshes) and an accelerated structure answer the same way.
#include <array>
#include <cstdint>
#include <optional>
#include <span>

#include "contact/closest_point.hpp"
#include "core/math.hpp"
#include "mesh/tri_mesh.hpp"

namespace tactus::contact {

/// The surface point closest to a query point p, and which side of the surface p is on.
struct ClosestSurfacePoint {
  bool found = false;            ///< false when the surface is empty
  std::int32_t triangle = -1;    ///< -1 for surfaces that are not triangles (a half-space)
  Vec3 point = Vec3::Zero();
  Vec3 barycentric = Vec3::Zero();
  /// Unit outward normal at `point`: the face normal inside a face, the angle-weighted
  /// pseudo-normal on an edge or a vertex (Bærentzen & Aanæs 2005), so that the sign of
  /// (p − point)·normal tells the side of a closed, outward-oriented surface exactly.
  Vec3 normal = Vec3::UnitZ();
  double distance = 0.0;  ///< |p − point|
  bool behind = false;    ///< (p − point)·normal < 0: p is on the inner side
};

/// First contact of a sphere moving along a segment.
struct SweepHit {
  bool hit = false;
  double time = 1.0;           ///< fraction of the segment at first contact, in [0, 1]
  std::int32_t triangle = -1;  ///< -1 for surfaces that are not triangles
  Vec3 center = Vec3::Zero();  ///< the sphere's centre at first contact
  Vec3 point = Vec3::Zero();   ///< contact point on the surface
  Vec3 barycentric = Vec3::Zero();
  /// Unit, from `point` toward `center`: the side the sphere came from (a back face hit
  /// from behind gives the reversed face normal).
  Vec3 normal = Vec3::UnitZ();
};

class SurfaceQuery {
 public:
  virtual ~SurfaceQuery() = default;
  SurfaceQuery() = default;
  SurfaceQuery(const SurfaceQuery&) = default;
  SurfaceQuery& operator=(const SurfaceQuery&) = default;

  [[nodiscard]] virtual ClosestSurfacePoint closest_point(const Vec3& p) const = 0;

  /// The earliest time t in [0, 1] at which the sphere of `radius` centred on
  /// from + t·(to − from) touches the surface (distance ≤ radius), faces, edges and
  /// vertices alike, from either side. A sphere that already overlaps a triangle at t = 0
  /// hits it at t = 0 when it moves toward it and ignores it when it moves away (its
  /// distance to that triangle can then only grow).
  [[nodiscard]] virtual SweepHit sweep_sphere(const Vec3& from, const Vec3& to, double radius) const = 0;

  /// Current corner positions of triangle t; nullopt when t is not a triangle of this surface.
  [[nodiscard]] virtual std::optional<std::array<Vec3, 3>> triangle(std::int32_t t) const = 0;
};

/// Sphere of `radius` swept from `from` to `to` against triangle (a, b, c), by the rules of
/// SurfaceQuery::sweep_sphere. Exact earliest time of impact: the entry into the face slab
/// where the contact lies inside the face, the edges as cylinders, the vertices as spheres.
[[nodiscard]] SweepHit sweep_sphere_triangle(const Vec3& from, const Vec3& to, double radius, const Vec3& a,
                                             const Vec3& b, const Vec3& c);

/// The weight of triangle (a, b, c) in the angle-weighted pseudo-normal at a point with
/// these barycentric coordinates: the triangle's angle at a vertex, π on an edge, 2π inside.
[[nodiscard]] double pseudo_normal_weight(const Vec3& barycentric, const Vec3& a, const Vec3& b, const Vec3& c);

/// The side of the surface at a closest point, shared by every SurfaceQuery so that they
/// answer alike: the angle-weighted pseudo-normal at `closest` (the surface point closest
/// to p) is the sum of term() over the triangles near it, in ascending triangle index.
/// Inside a face no neighbours are needed (on_edge_or_vertex() is false); otherwise only
/// triangles whose box overlaps [lo(), hi()] can contribute.
class PseudoNormalSum {
 public:
  PseudoNormalSum(const Vec3& p, const SurfacePoint& closest);

  [[nodiscard]] bool on_edge_or_vertex() const { return on_edge_or_vertex_; }
  [[nodiscard]] const Vec3& lo() const { return lo_; }
  [[nodiscard]] const Vec3& hi() const { return hi_; }
  /// What triangle (a, b, c) adds: its unit normal times pseudo_normal_weight when its own
  /// closest point to p is the shared one (within a relative 1e-10), zero otherwise.
  [[nodiscard]] Vec3 term(const Vec3& a, const Vec3& b, const Vec3& c) const;
  /// The answer for p given the sum of the terms (ignored inside a face).
  [[nodiscard]] ClosestSurfacePoint result(const Vec3& sum) const;

 private:
  Vec3 p_;
  SurfacePoint closest_;
  bool on_edge_or_vertex_;
  double tolerance_;
  Vec3 lo_, hi_;
};

/// SurfaceQuery by visiting every triangle: O(triangles) per query, no allocation. It reads
/// the positions through the span on every query, so a deforming surface updated in place
/// is seen at once.
class BruteForceSurfaceQuery final : public SurfaceQuery {
 public:
  /// Throws InputError when a triangle refers to a vertex that does not exist.
  BruteForceSurfaceQuery(std::span<const Vec3> positions, std::span<const mesh::Triangle> triangles);

  [[nodiscard]] ClosestSurfacePoint closest_point(const Vec3& p) const override;
  [[nodiscard]] SweepHit sweep_sphere(const Vec3& from, const Vec3& to, double radius) const override;
  [[nodiscard]] std::optional<std::array<Vec3, 3>> triangle(std::int32_t t) const override;

 private:
  std::span<const Vec3> positions_;
  std::span<const mesh::Triangle> triangles_;
};

/// The plane {x : normal·x = offset} seen as the boundary of the half-space behind it: the
/// local model of a contact between surface updates. `normal` must be unit.
class HalfSpaceQuery final : public SurfaceQuery {
 public:
  HalfSpaceQuery(const Vec3& normal, double offset) : normal_(normal), offset_(offset) {}

  [[nodiscard]] ClosestSurfacePoint closest_point(const Vec3& p) const override;
  [[nodiscard]] SweepHit sweep_sphere(const Vec3& from, const Vec3& to, double radius) const override;
  [[nodiscard]] std::optional<std::array<Vec3, 3>> triangle(std::int32_t) const override { return std::nullopt; }

 private:
  Vec3 normal_;
  double offset_;
};

}  // namespace tactus::contact
