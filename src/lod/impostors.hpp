#pragma once
// Multi-resolution impostor hierarchies of a closed surface (seed 000 §4.1): levels from
// coarse to fine, coarser ones by quadric-error decimation of the input, finer ones by Loop
// subdivision of it, each holding what a haptic loop queries (a triangle BVH, per-vertex
// curvature) and what a level selection weighs (its error against the finest level and its
// measured cost). docs/lod.md describes the levels, the choices and the numbers.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "contact/bvh.hpp"
#include "core/math.hpp"
#include "mesh/curvature.hpp"
#include "mesh/tri_mesh.hpp"

namespace tactus::lod {

struct ImpostorParams {
  /// Levels coarser than the input, each by decimation of the next finer one; 0 to 8.
  int coarse_levels = 2;
  /// Triangles of a coarser level over those of the next finer one, in (0, 1).
  double reduction = 0.25;
  /// Levels finer than the input, each one step of Loop subdivision; 0 to 2.
  int subdivision_levels = 1;
  /// Physical radius of the curvature neighbourhood: each level's q-ring count is this over
  /// its mean edge length, rounded, clamped to [kDefaultRings, kMaxRings] of
  /// CurvatureEstimator (one ring gives too few votes: 33 % worst error on a sphere against
  /// 5 % with two). So the rings grow toward finer levels and the neighbourhood keeps its
  /// size, except on levels coarser than the radius allows, which keep two rings and so
  /// vote over a wider patch. 0 picks kDefaultRings mean edge lengths of the input.
  double curvature_radius = 0.0;
  /// Points sampled on a surface (area-weighted, besides its vertices) for the Hausdorff and
  /// curvature errors; ≥ 16.
  int error_samples = 4096;
  /// Points near the finest surface at which a closest-point query is timed; ≥ 16.
  int cost_queries = 2048;
  /// Seed of the sample points (the errors are a function of the mesh and the parameters).
  std::uint64_t seed = 1;

  friend bool operator==(const ImpostorParams&, const ImpostorParams&) = default;
};

/// Throws InputError naming the parameter that is out of range.
void check_params(const ImpostorParams& params);

/// A level's distance from the finest level.
struct LevelError {
  double hausdorff = 0.0;      ///< symmetric Hausdorff distance (sampled), m
  double curvature_rms = 0.0;  ///< RMS of the mean-curvature difference at samples, 1/m
  friend bool operator==(const LevelError&, const LevelError&) = default;
};

/// What a level costs, measured on the machine that built it.
struct LevelCost {
  double query_p50 = 0.0;  ///< median time of one closest_point_with_side, s
  double query_p99 = 0.0;  ///< 99th percentile, s
  double build_time = 0.0;  ///< decimation or subdivision, BVH and curvature, s
  std::size_t triangles = 0;  ///< the draw-cost proxy
  friend bool operator==(const LevelCost&, const LevelCost&) = default;
};

/// One level: a closed, outward-oriented surface and its haptic data.
struct ImpostorLevel {
  mesh::TriMesh mesh;
  contact::TriangleBvh bvh;
  int rings = mesh::CurvatureEstimator::kDefaultRings;  ///< q of the curvature neighbourhood
  /// Per vertex, from mesh::CurvatureEstimator over `rings` rings.
  std::vector<mesh::VertexCurvature> curvature;
  double mean_edge = 0.0;  ///< mean edge length, m
  LevelError error;
  LevelCost cost;

  /// Mean curvature at a surface point given by a triangle and barycentric weights (as a
  /// closest-point query returns them): the vertices' values blended by the weights.
  [[nodiscard]] double mean_curvature_at(std::int32_t triangle, const Vec3& barycentric) const;
};

struct ImpostorHierarchy {
  std::vector<ImpostorLevel> levels;  ///< coarse to fine
  std::size_t input_level = 0;        ///< the level that is the input mesh itself
  std::uint64_t mesh_hash = 0;        ///< TriMesh::content_hash() of the input
  ImpostorParams params;
  /// params.curvature_radius, or the radius it picks when 0, m.
  double curvature_radius = 0.0;

  [[nodiscard]] std::size_t coarsest() const { return 0; }
  [[nodiscard]] std::size_t finest() const { return levels.size() - 1; }
};


/// Throws InputError (saying what is wrong, with `what` naming the mesh) unless the mesh is
/// a closed, outward-oriented manifold with finite vertices and no unused vertex.
void check_closed_surface(const mesh::TriMesh& mesh, const std::string& what);

/// The hierarchy of `input` (checked by check_closed_surface): its levels' meshes, BVHs,
/// curvatures, errors and costs.
[[nodiscard]] ImpostorHierarchy build_impostors(const mesh::TriMesh& input, const ImpostorParams& params = {});

/// Fills a level's BVH, ring count, curvature and mean edge from its mesh (how a cache load
/// restores a level); `curvature_radius` as resolved for the hierarchy.
void prepare_level(ImpostorLevel& level, double curvature_radius);

/// The q-ring count for a level: curvature_radius / mean_edge rounded, in
/// [CurvatureEstimator::kDefaultRings, CurvatureEstimator::kMaxRings].
[[nodiscard]] int rings_for(double curvature_radius, double mean_edge);

/// Mean edge length of a closed mesh (each edge once).
[[nodiscard]] double mean_edge_length(const mesh::TriMesh& mesh);

/// Symmetric Hausdorff distance between two surfaces, sampled: the vertices of each and
/// `samples` area-weighted random points on each (from `seed`), each to its closest point
/// on the other surface through that surface's BVH. Exact at the samples; a lower bound of
/// the true distance that tightens with the sample count.
[[nodiscard]] double hausdorff_distance(const mesh::TriMesh& a, const contact::TriangleBvh& bvh_a,
                                        const mesh::TriMesh& b, const contact::TriangleBvh& bvh_b, int samples,
                                        std::uint64_t seed);

/// `count` area-weighted random points on a mesh: triangle index and barycentric weights.
struct SurfaceSample {
  std::int32_t triangle = 0;
  Vec3 barycentric = Vec3::Zero();
  Vec3 point = Vec3::Zero();
};
[[nodiscard]] std::vector<SurfaceSample> sample_surface(const mesh::TriMesh& mesh, int count, std::uint64_t seed);

}  // namespace tactus::lod
