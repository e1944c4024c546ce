// Triangle BVH on deforming surfaces: build, refit, closest point (random points near the
// surface), all-hits raycast and the inside test, against the brute-force scans, on
// liver-sized organ surfaces (~1k, 10k, 100k triangles) and icospheres (82k ... 1.3M).
// Every query and refit is timed on its own. Closest points are asked at random points near
// the surface (each query far from the last: caches mostly cold) and along a path (each
// near the last, as a haptic loop asks them).
// Counters: triangles, median_us and p99_us per operation (clock overhead included, tens of
// ns), quality (refit), hits (raycast, mean per ray).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <map>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "contact/bvh.hpp"
#include "mesh/generators.hpp"

namespace {

using namespace tactus;
using namespace tactus::contact;

struct MeshSpec {
  const char* name;
  bool organ;
  int resolution;  ///< organ cells along its length, or sphere subdivisions
};

constexpr std::array<MeshSpec, 6> kMeshes{{{"organ", true, 10},    // 1,104 triangles
                                           {"organ", true, 30},    // 10,320
                                           {"organ", true, 93},    // ~100k
                                           {"sphere", false, 6},   // 81,920
                                           {"sphere", false, 7},   // 327,680
                                           {"sphere", false, 8}}};  // 1,310,720

/// A surface and a few frames of it deforming (a travelling wave of 5 % of its size).
struct Scene {
  mesh::TriMesh mesh;
  std::vector<std::vector<Vec3>> frames;
  double size = 0.0;
};

const Scene& scene(std::int64_t id) {
  static std::map<std::int64_t, Scene> cache;
  auto it = cache.find(id);
  if (it != cache.end()) return it->second;
  const MeshSpec& spec = kMeshes[static_cast<std::size_t>(id)];
  Scene s;
  s.mesh = spec.organ ? mesh::organ(0.22, spec.resolution) : mesh::sphere(0.05, spec.resolution);
  s.size = s.mesh.bounds().size().norm();
  const Vec3 k = Vec3(1.0, 0.6, 0.3).normalized() * (2.0 * std::numbers::pi / s.size);
  for (int f = 0; f < 8; ++f) {
    std::vector<Vec3> x = s.mesh.vertices;
    for (Vec3& p : x) p += 0.05 * s.size * std::sin(k.dot(p) + 0.7 * f) * Vec3(0.2, 0.3, 1.0).normalized();
    s.frames.push_back(std::move(x));
  }
  return cache.emplace(id, std::move(s)).first->second;
}

/// Points within ±1 % of the size from random vertices.
std::vector<Vec3> points_near(const std::vector<Vec3>& x, double size, std::size_t n) {
  std::mt19937 rng(5);
  std::uniform_int_distribution<std::size_t> pick(0, x.size() - 1);
  std::uniform_real_distribution<double> u(-0.01 * size, 0.01 * size);
  std::vector<Vec3> out(n);
  for (Vec3& p : out) p = x[pick(rng)] + Vec3(u(rng), u(rng), u(rng));
  return out;
}

class Timer {
 public:
  void start() { t0_ = std::chrono::steady_clock::now(); }
  void stop() { samples_.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0_).count()); }
  void report(benchmark::State& state) {
    std::sort(samples_.begin(), samples_.end());
    state.counters["median_us"] = samples_[samples_.size() / 2];
    state.counters["p99_us"] = samples_[std::min(samples_.size() - 1, samples_.size() * 99 / 100)];
  }
  void report(benchmark::State& state, const Scene& s) {
    report(state);
    state.counters["triangles"] = static_cast<double>(s.mesh.triangles.size());
    state.SetLabel(kMeshes[static_cast<std::size_t>(state.range(0))].name);
  }

 private:
  std::chrono::steady_clock::time_point t0_;
  std::vector<double> samples_;
};

void BM_Build(benchmark::State& state) {
  const Scene& s = scene(state.range(0));
  TriangleBvh bvh;
  Timer timer;
  std::size_t f = 0;
  for (auto _ : state) {
    timer.start();
    bvh.build(s.frames[f++ % s.frames.size()], s.mesh.triangles);
    timer.stop();
  }
  timer.report(state, s);
  state.counters["depth"] = bvh.depth();
}

void BM_Refit(benchmark::State& state) {
  const Scene& s = scene(state.range(0));
  TriangleBvh bvh(s.mesh.vertices, s.mesh.triangles);
  Timer timer;
  std::size_t f = 0;
  for (auto _ : state) {
    timer.start();
    bvh.refit(s.frames[f++ % s.frames.size()]);
    timer.stop();
  }
  timer.report(state, s);
  state.counters["quality"] = bvh.quality();
}

void BM_ClosestPoint(benchmark::State& state) {
  const Scene& s = scene(state.range(0));
  TriangleBvh bvh(s.mesh.vertices, s.mesh.triangles);
  bvh.refit(s.frames[3]);
  const auto points = points_near(s.frames[3], s.size, 4096);
  Timer timer;
  std::size_t i = 0;
  for (auto _ : state) {
    timer.start();
    benchmark::DoNotOptimize(bvh.closest_point(points[i++ % points.size()]));
    timer.stop();
  }
  timer.report(state, s);
}

/// A tool tip gliding `offset` outside the surface around a closed loop in 4096 steps
/// (about 0.1 mm apart: 0.1 m/s at the 1 kHz haptic rate): the coherent queries of a
/// haptic loop.
std::vector<Vec3> path_near(const TriangleBvh& bvh, std::size_t n, double offset) {
  std::vector<Vec3> out;
  std::vector<RayHit> hits;
  for (std::size_t i = 0; i < n; ++i) {
    const double a = 2.0 * std::numbers::pi * static_cast<double>(i) / static_cast<double>(n);
    const Vec3 d = Vec3(std::cos(a), 0.8 * std::sin(a), 0.3 * std::sin(3.0 * a)).normalized();
    bvh.raycast(Vec3::Zero(), d, std::numeric_limits<double>::infinity(), hits);  // the centre is inside
    if (!hits.empty()) out.push_back(hits.back().point + offset * d);
  }
  return out;
}

void BM_ClosestPointAlongPath(benchmark::State& state) {
  const Scene& s = scene(state.range(0));
  TriangleBvh bvh(s.mesh.vertices, s.mesh.triangles);
  bvh.refit(s.frames[3]);
  const double offset = 1e-6 * static_cast<double>(state.range(1));
  const auto points = path_near(bvh, 4096, offset);
  Timer timer;
  std::size_t i = 0;
  for (auto _ : state) {
    timer.start();
    benchmark::DoNotOptimize(bvh.closest_point(points[i++ % points.size()]));
    timer.stop();
  }
  timer.report(state, s);
  state.counters["offset_mm"] = 1e3 * offset;
}

void BM_ClosestPointBruteForce(benchmark::State& state) {
  const Scene& s = scene(state.range(0));
  const auto points = points_near(s.frames[3], s.size, 4096);
  Timer timer;
  std::size_t i = 0;
  for (auto _ : state) {
    timer.start();
    benchmark::DoNotOptimize(closest_point_on_surface(points[i++ % points.size()], s.frames[3], s.mesh.triangles));
    timer.stop();
  }
  timer.report(state, s);
}

/// Rays from outside the surface's box through random points near it, every hit.
template <bool kBruteForce>
void BM_RaycastAllHits(benchmark::State& state) {
  const Scene& s = scene(state.range(0));
  TriangleBvh bvh(s.mesh.vertices, s.mesh.triangles);
  bvh.refit(s.frames[3]);
  const auto targets = points_near(s.frames[3], s.size, 4096);
  std::mt19937 rng(6);
  std::normal_distribution<double> n(0.0, 1.0);
  std::vector<std::pair<Vec3, Vec3>> rays;
  for (const Vec3& t : targets) {
    const Vec3 d = Vec3(n(rng), n(rng), n(rng)).normalized();
    rays.emplace_back(t - s.size * d, d);
  }
  std::vector<RayHit> hits;
  hits.reserve(64);
  Timer timer;
  std::size_t i = 0, total_hits = 0, rays_cast = 0;
  const double inf = std::numeric_limits<double>::infinity();
  for (auto _ : state) {
    const auto& [origin, direction] = rays[i++ % rays.size()];
    timer.start();
    if constexpr (kBruteForce)
      raycast_surface(origin, direction, inf, s.frames[3], s.mesh.triangles, hits);
    else
      bvh.raycast(origin, direction, inf, hits);
    timer.stop();
    total_hits += hits.size();
    ++rays_cast;
  }
  timer.report(state, s);
  state.counters["hits"] = static_cast<double>(total_hits) / static_cast<double>(rays_cast);
}

void BM_Inside(benchmark::State& state) {
  const Scene& s = scene(state.range(0));
  TriangleBvh bvh(s.mesh.vertices, s.mesh.triangles);
  bvh.refit(s.frames[3]);
  const auto points = points_near(s.frames[3], s.size, 4096);
  Timer timer;
  std::size_t i = 0;
  for (auto _ : state) {
    timer.start();
    benchmark::DoNotOptimize(bvh.inside(points[i++ % points.size()]));
    timer.stop();
  }
  timer.report(state, s);
}

/// Volume nodes near a needle: the nodes of an organ-sized box of tetrahedra (~100k nodes),
/// refitted each step, queried with 3 cm needles within 2 mm.
void BM_PointTree(benchmark::State& state) {
  const bool refit = state.range(0) == 0;
  const mesh::TetMesh volume = mesh::box_volume(Vec3(0.2, 0.15, 0.08), 60, 45, 36);
  PointTree tree(volume.vertices);
  std::vector<Vec3> moved = volume.vertices;
  for (Vec3& p : moved) p.z() += 0.004 * std::sin(30.0 * p.x());
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.06, 0.06);
  std::vector<std::int32_t> out;
  out.reserve(volume.vertices.size());
  Timer timer;
  std::size_t found = 0, n = 0;
  for (auto _ : state) {
    const Vec3 a(u(rng), u(rng), 0.05), b = a + Vec3(0.005, 0.002, -0.03);
    timer.start();
    if (refit)
      tree.refit(n % 2 == 0 ? moved : volume.vertices);
    else
      tree.nodes_near_segment(a, b, 0.002, out);
    timer.stop();
    found += out.size();
    ++n;
  }
  timer.report(state);
  state.counters["points"] = static_cast<double>(volume.vertices.size());
  if (!refit) state.counters["found"] = static_cast<double>(found) / static_cast<double>(n);
  state.SetLabel(refit ? "refit" : "nodes_near_segment");
}

void small(benchmark::internal::Benchmark* b) {
  for (int m : {0, 1}) b->Arg(m);
}
void organs(benchmark::internal::Benchmark* b) {
  for (int m : {0, 1, 2}) b->Arg(m);
}
void all(benchmark::internal::Benchmark* b) {
  for (int m = 0; m < static_cast<int>(kMeshes.size()); ++m) b->Arg(m);
}
void all_at_offsets(benchmark::internal::Benchmark* b) {
  for (int offset_um : {100, 1000})
    for (int m = 0; m < static_cast<int>(kMeshes.size()); ++m) b->Args({m, offset_um});
}

BENCHMARK(BM_Build)->Apply(organs)->Arg(3)->Unit(benchmark::kMillisecond)->MinTime(0.5);
BENCHMARK(BM_Refit)->Apply(organs)->Arg(3)->Arg(4)->Unit(benchmark::kMicrosecond)->MinTime(0.5);
BENCHMARK(BM_ClosestPoint)->Apply(all)->Unit(benchmark::kMicrosecond)->MinTime(0.5);
BENCHMARK(BM_ClosestPointAlongPath)->Apply(all_at_offsets)->Unit(benchmark::kMicrosecond)->MinTime(0.5);
BENCHMARK(BM_ClosestPointBruteForce)->Apply(small)->Unit(benchmark::kMicrosecond)->MinTime(0.5);
BENCHMARK(BM_RaycastAllHits<false>)->Apply(all)->Unit(benchmark::kMicrosecond)->MinTime(0.5);
BENCHMARK(BM_RaycastAllHits<true>)->Apply(small)->Unit(benchmark::kMicrosecond)->MinTime(0.5);
BENCHMARK(BM_Inside)->Apply(organs)->Unit(benchmark::kMicrosecond)->MinTime(0.5);
BENCHMARK(BM_PointTree)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond)->MinTime(0.5);

}  // namespace

BENCHMARK_MAIN();
