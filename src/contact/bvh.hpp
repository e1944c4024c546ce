#pragma once
// Bounding volume hierarchies for collision queries on deforming meshes: a triangle tree
// (closest point, every ray hit, sphere overlap, inside/outside) and a point tree (volume
// nodes near a tool segment). Both are built once per topology and refitted each
// simulation step: a refit is O(n) and allocates nothing, and so are the queries (except
// for growing a result vector that the caller passes in and reuses). Every answer is
// deterministic: ties go to the lowest triangle or point index.
#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <vector>

#include "contact/closest_point.hpp"
#include "contact/surface_query.hpp"
#include "core/math.hpp"
#include "mesh/tri_mesh.hpp"

namespace tactus::contact {

/// One crossing of a ray with a triangle.
struct RayHit {
  double t = 0.0;                   ///< the hit is origin + t · direction
  std::int32_t triangle = -1;
  Vec3 barycentric = Vec3::Zero();  ///< weights of the triangle's vertices a, b, c
  Vec3 point = Vec3::Zero();        ///< on the triangle (the barycentric combination)
  Vec3 normal = Vec3::Zero();       ///< unit face normal; zero if the triangle is degenerate
  bool entering = false;            ///< direction · normal < 0 (into an outward mesh)
};

/// Every hit of the ray origin + t · direction, 0 ≤ t ≤ max_t, with the triangles over
/// `positions`, by testing every triangle; sorted by t, then triangle index. The reference
/// for TriangleBvh::raycast: the same watertight test, so the same answer.
void raycast_surface(const Vec3& origin, const Vec3& direction, double max_t, std::span<const Vec3> positions,
                     std::span<const mesh::Triangle> triangles, std::vector<RayHit>& hits);

namespace detail {
/// An inner node of a flat hierarchy holding both children's boxes (single precision,
/// rounded outward), so that one cache line decides where to descend. A child reference
/// ≥ 0 is an inner node (always after its parent in the array); < 0 is a leaf owning the
/// slots [−ref − 1, −ref − 1 + count) of the tree's item order.
struct alignas(64) BvhNode {
  float lo[3][2];  ///< [axis][child]
  float hi[3][2];
  std::int32_t child[2];
  std::uint8_t count[2];  ///< items of a leaf child; 0 for an inner child
};

/// A leaf: its slots and where its box is stored (child `side` of inner node `parent`;
/// parent −1 for a root leaf).
struct BvhLeaf {
  std::int32_t first = 0;
  std::int32_t parent = -1;
  std::uint8_t count = 0;
  std::uint8_t side = 0;
};

/// The shared skeleton of both trees: inner nodes, leaves, the root and the item order.
struct BvhTopology {
  std::vector<BvhNode> nodes;
  std::vector<BvhLeaf> leaves;      ///< in slot order
  std::vector<std::int32_t> order;  ///< slot → item index
  std::int32_t root = 0;            ///< child reference of the root (see BvhNode)
  std::uint8_t root_count = 0;      ///< items when the root is a leaf
  Vec3 root_lo = Vec3::Zero(), root_hi = Vec3::Zero();
  int depth = 0;                    ///< levels, a root leaf counting one
  [[nodiscard]] bool empty() const { return order.empty(); }
};
}  // namespace detail

/// Triangle BVH over index triples and vertex positions that change every step. Binned-SAH
/// build (O(n log n), leaves of up to 4 triangles); refit keeps the topology and updates
/// the boxes. The tree keeps its own copy of the positions, so a built tree is a
/// self-contained snapshot: the caller's arrays may change under it, and const queries may
/// run on several threads at once (not during a build or refit of the same tree).
class TriangleBvh {
 public:
  static constexpr int kMaxLeafTriangles = 4;
  static constexpr int kMaxDepth = 64;
  /// quality() above which needs_rebuild() says a fresh build pays off (smooth tissue
  /// deformation stays near 1.0–1.1; triangles sliding across the surface exceed it).
  static constexpr double kDefaultRebuildQuality = 1.6;

  TriangleBvh() = default;
  TriangleBvh(std::span<const Vec3> positions, std::span<const mesh::Triangle> triangles) {
    build(positions, triangles);
  }

  /// Throws InputError for a vertex index out of range or a position that is not finite
  /// or beyond ±1e30 (boxes are kept in single precision).
  void build(std::span<const Vec3> positions, std::span<const mesh::Triangle> triangles);
  /// New positions for the same vertices (same count as at build); no allocation, O(n).
  /// Throws InputError for a wrong count or a bad position as in build (the tree is then
  /// left as it was).
  void refit(std::span<const Vec3> positions);

  /// Surface-area cost of the tree (Σ node area / root area, leaves weighted by their
  /// triangle count) now, divided by that right after the last build: 1 after a build,
  /// growing as refits stretch boxes over moved triangles. Unchanged by translation and
  /// uniform scaling (not by rotation: the boxes are axis-aligned).
  [[nodiscard]] double quality() const { return quality_; }
  [[nodiscard]] bool needs_rebuild(double max_quality = kDefaultRebuildQuality) const {
    return quality_ > max_quality;
  }

  /// The closest surface point to p no farther than max_distance (triangle −1 when there
  /// is none or the tree is empty), by a nearest-child-first descent that prunes boxes
  /// farther than the best so far. Same answer as closest_point_on_surface over the same
  /// positions. Throws InputError for a non-finite p or a negative or NaN max_distance.
  [[nodiscard]] SurfacePoint closest_point(const Vec3& p,
                                           double max_distance = std::numeric_limits<double>::infinity()) const;
  /// closest_point(p) with the side of the surface p is on (the angle-weighted
  /// pseudo-normal on an edge or a vertex, from the triangles near it): the same answer as
  /// BruteForceSurfaceQuery::closest_point over the same positions. Throws InputError for a
  /// non-finite p.
  [[nodiscard]] ClosestSurfacePoint closest_point_with_side(const Vec3& p) const;
  /// The first contact of a sphere of `radius` moving from `from` to `to`, by the rules of
  /// SurfaceQuery::sweep_sphere, and the same answer as BruteForceSurfaceQuery::sweep_sphere
  /// over the same positions (the earliest time; ties to the lowest triangle index). The
  /// segment is clipped against the node boxes grown by the radius, up to the earliest
  /// contact found so far, nearer boxes first. Throws InputError for non-finite ends or a
  /// negative or NaN radius.
  [[nodiscard]] SweepHit sweep_sphere(const Vec3& from, const Vec3& to, double radius) const;
  /// Every hit with 0 ≤ t ≤ max_t into `hits` (cleared first), sorted by t then triangle:
  /// all layers, for palpation through several surfaces. Watertight (Woop, Benthin & Wald
  /// 2013) with a consistent tie rule on shared edges and vertices, so a ray that crosses
  /// a closed mesh through an edge or a vertex counts one crossing there. Throws
  /// InputError for a zero or non-finite direction, a non-finite origin or a negative or
  /// NaN max_t.
  void raycast(const Vec3& origin, const Vec3& direction, double max_t, std::vector<RayHit>& hits) const;
  /// raycast limited to the segment a → b: t is the fraction of the way from a to b.
  /// A zero-length segment has no hits.
  void segment(const Vec3& a, const Vec3& b, std::vector<RayHit>& hits) const;
  /// Triangles whose closest point to center is within radius, ascending, into `triangles`
  /// (cleared first). Throws InputError for a non-finite center or a negative or NaN radius.
  void sphere_overlap(const Vec3& center, double radius, std::vector<std::int32_t>& triangles) const;
  /// Whether p is inside a closed, outward-oriented surface, by the parity of crossings of
  /// a fixed non-axis ray (a second ray when the first meets an edge, a vertex or an
  /// edge-on triangle exactly). Points on the surface may go either way.
  [[nodiscard]] bool inside(const Vec3& p) const;

  [[nodiscard]] bool empty() const { return tree_.empty(); }
  [[nodiscard]] std::size_t triangle_count() const { return triangles_.size(); }
  [[nodiscard]] std::size_t vertex_count() const { return vertex_count_; }
  [[nodiscard]] std::size_t node_count() const { return tree_.nodes.size(); }
  /// Appends the boxes (lo, hi) of the nodes from the root (level 0) down to `levels`
  /// levels below it, for display (the viewer's debug view). Allocates as `out` grows.
  void node_boxes(int levels, std::vector<std::pair<Vec3, Vec3>>& out) const;
  [[nodiscard]] int depth() const { return tree_.depth; }
  /// A box around the whole surface (empty for an empty tree); it may exceed the exact
  /// bounds by a float rounding.
  [[nodiscard]] Aabb bounds() const;
  [[nodiscard]] std::span<const mesh::Triangle> triangles() const { return triangles_; }
  /// Corner positions of triangle t as of the last build or refit; nullopt when t is not a
  /// triangle of the tree.
  [[nodiscard]] std::optional<std::array<Vec3, 3>> triangle_corners(std::int32_t t) const;

 private:
  template <class Visit>
  void visit_ray(const Vec3& origin, const Vec3& direction, double max_t, Visit&& visit) const;
  template <class Bound, class Visit>
  void visit_near(const Vec3& p, Bound&& bound2, Visit&& visit) const;
  template <class Visit>
  void visit_box(const Vec3& lo, const Vec3& hi, Visit&& visit) const;
  int crossing_parity(const Vec3& p, const Vec3& direction, bool& degenerate) const;
  /// Boxes from positions_; returns the tree's surface-area cost (quality() before dividing).
  double update_boxes();
  [[nodiscard]] double margin(const Vec3& query) const;

  detail::BvhTopology tree_;
  std::size_t vertex_count_ = 0;
  std::vector<mesh::Triangle> triangles_;          ///< as given
  /// A triangle as a leaf stores it: corners in the tree's own vertex numbering (vertices
  /// are renumbered in leaf order so that a leaf's corners sit close together in memory)
  /// and the caller's triangle index, side by side so that a leaf reads one cache line.
  struct SlotTriangle {
    mesh::Triangle corners;
    std::int32_t triangle;
  };
  std::vector<SlotTriangle> slots_;
  std::vector<std::int32_t> slot_of_;        ///< caller's triangle index → slot
  std::vector<std::int32_t> vertex_source_;  ///< tree vertex → caller's vertex index
  std::vector<Vec3> positions_;              ///< in the tree's vertex numbering
  std::vector<std::int32_t> leaf_vertices_;      ///< each leaf's distinct corners (tree numbering)
  std::vector<std::int32_t> leaf_vertex_first_;  ///< leaf → its first entry there; one past the end last
  double build_cost_ = 0.0;
  double quality_ = 1.0;
  double abs_max_ = 0.0;  ///< largest |coordinate| of the surface: sets rounding margins
};

/// Static kd-tree over points (e.g. the nodes of a volume mesh) whose boxes are refitted
/// as the points move: proximity of nodes to a needle or tool segment.
class PointTree {
 public:
  static constexpr int kMaxLeafPoints = 8;
  static constexpr int kMaxDepth = 64;

  PointTree() = default;
  explicit PointTree(std::span<const Vec3> points) { build(points); }

  /// Throws InputError for a point that is not finite or beyond ±1e30.
  void build(std::span<const Vec3> points);
  /// Same count as at build; no allocation, O(n). Throws InputError for a wrong count or
  /// a bad point as in build (the tree is then left as it was).
  void refit(std::span<const Vec3> points);

  /// Points within distance r of the segment a → b (a point when a = b), ascending, into
  /// `out` (cleared first). Throws InputError for non-finite ends or a negative or NaN r.
  void nodes_near_segment(const Vec3& a, const Vec3& b, double r, std::vector<std::int32_t>& out) const;

  [[nodiscard]] bool empty() const { return tree_.empty(); }
  [[nodiscard]] std::size_t point_count() const { return tree_.order.size(); }
  [[nodiscard]] int depth() const { return tree_.depth; }

 private:
  detail::BvhTopology tree_;
  std::vector<Vec3> points_;  ///< in slot order
  double abs_max_ = 0.0;
};

}  // namespace tactus::contact
