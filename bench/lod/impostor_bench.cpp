// Impostor hierarchies (coarse_levels 2 at ×0.25, one Loop level, the defaults) of an organ
// surface and an icosphere: per level, its triangles, build time, Hausdorff distance and
// curvature RMS against the finest level, and the closest-point query time measured by the
// build (p50, p99: each query timed on its own, clock overhead included). The benchmark's
// own time is closest_point_with_side at the same kind of points (near the surface, each
// far from the last). Plus the whole build per shape. Counters: triangles, rings, build_ms,
// hausdorff_um, curv_rms_rel (curvature RMS × the shape's size), p50_us, p99_us.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "lod/impostors.hpp"
#include "mesh/generators.hpp"

namespace {

using namespace tactus;

struct Shape {
  const char* name;
  mesh::TriMesh mesh;
  double size;  ///< radius or half-length, m: curvature × size is dimensionless
};

const std::vector<Shape>& shapes() {
  static const std::vector<Shape> all{{"organ", mesh::organ(0.12, 48), 0.06}, {"sphere", mesh::sphere(0.05, 4), 0.05}};
  return all;
}

const lod::ImpostorHierarchy& hierarchy(std::size_t shape) {
  static std::map<std::size_t, lod::ImpostorHierarchy> built;
  auto it = built.find(shape);
  if (it == built.end()) it = built.emplace(shape, lod::build_impostors(shapes()[shape].mesh)).first;
  return it->second;
}

void BM_Level(benchmark::State& state) {
  const auto shape = static_cast<std::size_t>(state.range(0));
  const auto index = static_cast<std::size_t>(state.range(1));
  const lod::ImpostorHierarchy& h = hierarchy(shape);
  if (index >= h.levels.size()) {
    state.SkipWithError("no such level");
    return;
  }
  const lod::ImpostorLevel& level = h.levels[index];
  std::vector<Vec3> points;
  for (const lod::SurfaceSample& s : lod::sample_surface(h.levels.back().mesh, 1024, 99))
    points.push_back(s.point + 0.002 * h.levels.back().mesh.face_normal(static_cast<std::size_t>(s.triangle)));
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(level.bvh.closest_point_with_side(points[i]));
    i = (i + 1) % points.size();
  }
  state.SetLabel(std::string(shapes()[shape].name) + (index == h.input_level ? " input" : ""));
  state.counters["triangles"] = static_cast<double>(level.mesh.triangles.size());
  state.counters["rings"] = level.rings;
  state.counters["build_ms"] = level.cost.build_time * 1e3;
  state.counters["hausdorff_um"] = level.error.hausdorff * 1e6;
  state.counters["curv_rms_rel"] = level.error.curvature_rms * shapes()[shape].size;
  state.counters["p50_us"] = level.cost.query_p50 * 1e6;
  state.counters["p99_us"] = level.cost.query_p99 * 1e6;
}
BENCHMARK(BM_Level)->ArgsProduct({{0, 1}, {0, 1, 2, 3}})->ArgNames({"shape", "level"});

void BM_Build(benchmark::State& state) {
  const Shape& shape = shapes()[static_cast<std::size_t>(state.range(0))];
  for (auto _ : state) benchmark::DoNotOptimize(lod::build_impostors(shape.mesh));
  state.SetLabel(shape.name);
  state.counters["input_triangles"] = static_cast<double>(shape.mesh.triangles.size());
}
BENCHMARK(BM_Build)->Arg(0)->Arg(1)->ArgName("shape")->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace

BENCHMARK_MAIN();
