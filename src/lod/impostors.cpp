#include "lod/impostors.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>

#include "core/error.hpp"
#include "lod/remesh.hpp"
#include "mesh/half_edge.hpp"

namespace tactus::lod {
namespace {

/// splitmix64: a small generator whose output is the same with every standard library.
struct Random {
  std::uint64_t state;
  std::uint64_t next() {
    std::uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30U)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27U)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31U);
  }
  double uniform() { return static_cast<double>(next() >> 11U) * 0x1.0p-53; }  ///< [0, 1)
};

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// The value at fraction q of the sorted order (nearest rank).
double percentile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  const auto rank = static_cast<std::size_t>(std::ceil(q * static_cast<double>(values.size())));
  const std::size_t k = std::min(values.size() - 1, rank == 0 ? 0 : rank - 1);
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
  return values[k];
}

double directed_hausdorff(const mesh::TriMesh& from, const std::vector<SurfaceSample>& samples,
                          const contact::TriangleBvh& to) {
  double worst = 0.0;
  for (const Vec3& p : from.vertices) worst = std::max(worst, to.closest_point(p).distance);
  for (const SurfaceSample& s : samples) worst = std::max(worst, to.closest_point(s.point).distance);
  return worst;
}

/// Curvature RMS of `level` against the finest level at samples of the finest level.
double curvature_rms(const ImpostorLevel& level, const ImpostorLevel& finest,
                     const std::vector<SurfaceSample>& finest_samples) {
  if (finest_samples.empty()) return 0.0;
  double sum = 0.0;
  for (const SurfaceSample& s : finest_samples) {
    const double reference = finest.mean_curvature_at(s.triangle, s.barycentric);
    const contact::SurfacePoint near = level.bvh.closest_point(s.point);
    const double here = level.mean_curvature_at(near.triangle, near.barycentric);
    sum += (here - reference) * (here - reference);
  }
  return std::sqrt(sum / static_cast<double>(finest_samples.size()));
}

/// Points near the finest surface: samples moved off it along their face normal by a
/// fiftieth of the bounding-box diagonal, outward and inward in turn.
std::vector<Vec3> query_points(const mesh::TriMesh& finest, int count, std::uint64_t seed) {
  const std::vector<SurfaceSample> samples = sample_surface(finest, count, seed);
  const Aabb box = finest.bounds();
  const double offset = 0.02 * (box.max - box.min).norm();
  std::vector<Vec3> points;
  points.reserve(samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const double side = (i % 2 == 0) ? 1.0 : -1.0;
    points.push_back(samples[i].point +
                     side * offset * finest.face_normal(static_cast<std::size_t>(samples[i].triangle)));
  }
  return points;
}

void measure_queries(ImpostorLevel& level, const std::vector<Vec3>& points) {
  constexpr int kPasses = 3;
  double sink = 0.0;
  for (const Vec3& p : points) sink += level.bvh.closest_point_with_side(p).distance;  // warm the caches
  std::vector<double> times;
  times.reserve(points.size() * kPasses);
  for (int pass = 0; pass < kPasses; ++pass)
    for (const Vec3& p : points) {
      const auto start = std::chrono::steady_clock::now();
      sink += level.bvh.closest_point_with_side(p).distance;
      times.push_back(seconds_since(start));
    }
  // Keeps the queries from being optimised away.
  if (!std::isfinite(sink)) throw std::logic_error("lod: a closest-point distance is not finite");
  level.cost.query_p50 = percentile(times, 0.50);
  level.cost.query_p99 = percentile(times, 0.99);
}

void check_level(const mesh::TriMesh& m, const std::string& what) {
  try {
    check_closed_surface(m, what);
  } catch (const InputError& e) {
    // The input passed the same check, so the operation broke the surface.
    throw InputError(e.reason() + " (the input was closed and oriented: the operation could not keep it so)");
  }
}

}  // namespace

void check_params(const ImpostorParams& params) {
  if (params.coarse_levels < 0 || params.coarse_levels > 8)
    throw InputError("lod: coarse_levels must be in [0, 8], got " + std::to_string(params.coarse_levels));
  if (!(params.reduction > 0.0 && params.reduction < 1.0))
    throw InputError("lod: reduction must be in (0, 1), got " + std::to_string(params.reduction));
  if (params.subdivision_levels < 0 || params.subdivision_levels > 2)
    throw InputError("lod: subdivision_levels must be in [0, 2], got " + std::to_string(params.subdivision_levels));
  if (!(params.curvature_radius >= 0.0 && std::isfinite(params.curvature_radius)))
    throw InputError("lod: curvature_radius must be finite and ≥ 0, got " + std::to_string(params.curvature_radius));
  if (params.error_samples < 16 || params.error_samples > (1 << 24))
    throw InputError("lod: error_samples must be in [16, 2^24], got " + std::to_string(params.error_samples));
  if (params.cost_queries < 16 || params.cost_queries > (1 << 24))
    throw InputError("lod: cost_queries must be in [16, 2^24], got " + std::to_string(params.cost_queries));
}

void check_closed_surface(const mesh::TriMesh& m, const std::string& what) {
  if (m.triangles.empty()) throw InputError(what + ": has no triangles (a closed surface is needed)");
  for (std::size_t v = 0; v < m.vertices.size(); ++v)
    if (!m.vertices[v].allFinite()) throw InputError(what + ": vertex " + std::to_string(v) + " is not finite");
  std::optional<mesh::HalfEdgeMesh> half_edges;
  try {
    half_edges.emplace(m);
  } catch (const InputError& e) {
    throw InputError(what + ": not a consistently oriented manifold: " + e.reason());
  }
  if (!half_edges->closed())
    throw InputError(what + ": not closed (" + std::to_string(half_edges->num_boundary_half_edges()) +
                     " boundary edges)");
  for (std::size_t v = 0; v < m.vertices.size(); ++v)
    if (half_edges->outgoing(static_cast<mesh::Index>(v)) < 0)
      throw InputError(what + ": vertex " + std::to_string(v) + " is in no triangle");
  if (!(m.signed_volume() > 0.0))
    throw InputError(what + ": oriented inward (signed volume " + std::to_string(m.signed_volume()) +
                     " ≤ 0): triangles must be counter-clockwise seen from outside");
}

double mean_edge_length(const mesh::TriMesh& m) {
  double sum = 0.0;
  std::size_t count = 0;
  for (const mesh::Triangle& t : m.triangles)
    for (int k = 0; k < 3; ++k) {
      const mesh::Index a = t[static_cast<std::size_t>(k)];
      const mesh::Index b = t[static_cast<std::size_t>((k + 1) % 3)];
      if (a < b) {  // each edge of a closed oriented surface runs a < b in exactly one triangle
        sum += (m.vertices[static_cast<std::size_t>(a)] - m.vertices[static_cast<std::size_t>(b)]).norm();
        ++count;
      }
    }
  return count == 0 ? 0.0 : sum / static_cast<double>(count);
}

int rings_for(double curvature_radius, double mean_edge) {
  constexpr int kMin = mesh::CurvatureEstimator::kDefaultRings;
  if (!(mean_edge > 0.0)) return kMin;
  const double q = std::round(curvature_radius / mean_edge);
  return static_cast<int>(std::clamp(q, static_cast<double>(kMin), static_cast<double>(mesh::CurvatureEstimator::kMaxRings)));
}

double ImpostorLevel::mean_curvature_at(std::int32_t triangle, const Vec3& barycentric) const {
  if (triangle < 0 || static_cast<std::size_t>(triangle) >= mesh.triangles.size()) return 0.0;
  const Vec3 w = barycentric.cwiseMax(0.0);
  const double total = w.sum();
  if (!(total > 0.0)) return 0.0;
  const mesh::Triangle& t = mesh.triangles[static_cast<std::size_t>(triangle)];
  double k = 0.0;
  for (int i = 0; i < 3; ++i) k += w[i] * curvature[static_cast<std::size_t>(t[static_cast<std::size_t>(i)])].kmean;
  return k / total;
}

void prepare_level(ImpostorLevel& level, double curvature_radius) {
  level.bvh.build(level.mesh.vertices, level.mesh.triangles);
  level.mean_edge = mean_edge_length(level.mesh);
  level.rings = rings_for(curvature_radius, level.mean_edge);
  const mesh::HalfEdgeMesh half_edges(level.mesh);
  const mesh::CurvatureEstimator estimator(half_edges, level.rings);
  level.curvature.resize(level.mesh.vertices.size());
  for (std::size_t v = 0; v < level.mesh.vertices.size(); ++v)
    level.curvature[v] = estimator.estimate(level.mesh.vertices, static_cast<mesh::Index>(v));
  level.cost.triangles = level.mesh.triangles.size();
}

std::vector<SurfaceSample> sample_surface(const mesh::TriMesh& m, int count, std::uint64_t seed) {
  std::vector<SurfaceSample> samples;
  if (m.triangles.empty() || count <= 0) return samples;
  std::vector<double> cumulative(m.triangles.size());
  double total = 0.0;
  for (std::size_t t = 0; t < m.triangles.size(); ++t) cumulative[t] = (total += m.face_area(t));
  if (!(total > 0.0)) return samples;
  Random random{seed};
  samples.reserve(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) {
    const double u = random.uniform() * total;
    const auto it = std::upper_bound(cumulative.begin(), cumulative.end(), u);
    const std::size_t t = std::min(static_cast<std::size_t>(it - cumulative.begin()), m.triangles.size() - 1);
    const double s = std::sqrt(random.uniform());
    const double r = random.uniform();
    SurfaceSample sample;
    sample.triangle = static_cast<std::int32_t>(t);
    sample.barycentric = Vec3(1.0 - s, s * (1.0 - r), s * r);
    const mesh::Triangle& tri = m.triangles[t];
    for (int k = 0; k < 3; ++k)
      sample.point += sample.barycentric[k] * m.vertices[static_cast<std::size_t>(tri[static_cast<std::size_t>(k)])];
    samples.push_back(sample);
  }
  return samples;
}

double hausdorff_distance(const mesh::TriMesh& a, const contact::TriangleBvh& bvh_a, const mesh::TriMesh& b,
                          const contact::TriangleBvh& bvh_b, int samples, std::uint64_t seed) {
  const double ab = directed_hausdorff(a, sample_surface(a, samples, seed), bvh_b);
  const double ba = directed_hausdorff(b, sample_surface(b, samples, seed ^ 0x5a5a5a5a5a5a5a5aULL), bvh_a);
  return std::max(ab, ba);
}

ImpostorHierarchy build_impostors(const mesh::TriMesh& input, const ImpostorParams& params) {
  check_params(params);
  check_closed_surface(input, "lod: input mesh");
  ImpostorHierarchy h;
  h.params = params;
  h.mesh_hash = input.content_hash();
  h.curvature_radius = params.curvature_radius > 0.0
                           ? params.curvature_radius
                           : mesh::CurvatureEstimator::kDefaultRings * mean_edge_length(input);

  const auto levels = static_cast<std::size_t>(params.coarse_levels + 1 + params.subdivision_levels);
  h.levels.resize(levels);
  h.input_level = static_cast<std::size_t>(params.coarse_levels);

  auto start = std::chrono::steady_clock::now();
  h.levels[h.input_level].mesh = input;
  prepare_level(h.levels[h.input_level], h.curvature_radius);
  h.levels[h.input_level].cost.build_time = seconds_since(start);

  for (std::size_t l = h.input_level; l-- > 0;) {
    start = std::chrono::steady_clock::now();
    const mesh::TriMesh& finer = h.levels[l + 1].mesh;
    const auto target = static_cast<std::size_t>(
        std::max(4.0, std::round(params.reduction * static_cast<double>(finer.triangles.size()))));
    h.levels[l].mesh = decimate(finer, target);
    check_level(h.levels[l].mesh, "lod: decimated level " + std::to_string(l));
    prepare_level(h.levels[l], h.curvature_radius);
    h.levels[l].cost.build_time = seconds_since(start);
  }
  for (std::size_t l = h.input_level + 1; l < levels; ++l) {
    start = std::chrono::steady_clock::now();
    h.levels[l].mesh = loop_subdivide(h.levels[l - 1].mesh);
    check_level(h.levels[l].mesh, "lod: subdivided level " + std::to_string(l));
    prepare_level(h.levels[l], h.curvature_radius);
    h.levels[l].cost.build_time = seconds_since(start);
  }

  const ImpostorLevel& finest = h.levels.back();
  const std::vector<SurfaceSample> finest_samples = sample_surface(finest.mesh, params.error_samples, params.seed);
  for (std::size_t l = 0; l + 1 < levels; ++l) {
    ImpostorLevel& level = h.levels[l];
    level.error.hausdorff = hausdorff_distance(level.mesh, level.bvh, finest.mesh, finest.bvh,
                                               params.error_samples, params.seed + l);
    level.error.curvature_rms = curvature_rms(level, finest, finest_samples);
  }
  const std::vector<Vec3> queries = query_points(finest.mesh, params.cost_queries, params.seed ^ 0xc0575ULL);
  for (ImpostorLevel& level : h.levels) measure_queries(level, queries);
  return h;
}

}  // namespace tactus::lod
