// The haptic update on a deforming surface: collision queries + proxy update with friction +
// virtual-coupling force (update_proxy over a BvhSurfaceQuery), at 1 kHz, against organ
// surfaces of about 1k, 10k and 100k triangles that deform at a 100 Hz simulation rate:
// every 10th update the vertices move (a travelling wave, 2 % of the organ's size) and the
// tree is refitted. The refit is timed on its own, outside the haptic update.
//
// The device tip circles the organ at 0.1 m/s (0.1 mm per update), pressed in by up to 6 mm
// and lifted up to 2 mm clear once every 1.5 s: sliding contact with stick and slip, and a
// few free phases. The updates are paced at 1 kHz (sleeping until each next millisecond),
// as in the haptic loop: caches cool between updates, and a real-time priority (chrt -f)
// is not throttled as it would be under a back-to-back loop. Every update and every refit
// is timed with steady_clock (tens of ns of clock overhead included) into a histogram; after
// the run a table gives p50, p99, p99.9, max, mean and standard deviation in microseconds.
//
//   chrt -f 80 build/bvh/bench/bench_contact_haptic_update   (about 70 s)
#include <benchmark/benchmark.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <thread>
#include <utility>
#include <vector>

#include "contact/bvh.hpp"
#include "contact/bvh_surface_query.hpp"
#include "contact/proxy.hpp"
#include "core/histogram.hpp"
#include "mesh/generators.hpp"

namespace {

using namespace tactus;
using namespace tactus::contact;
using Clock = std::chrono::steady_clock;

constexpr double kHapticDt = 1e-3;     // 1 kHz
constexpr int kUpdatesPerStep = 10;    // the simulation runs at 100 Hz
constexpr int kWarmUpUpdates = 1000;   // one second, not recorded
constexpr int kUpdates = 20000;        // 20 s of haptic time per mesh
constexpr double kOrganLength = 0.22;  // liver-sized

struct MeshCase {
  const char* name;
  int resolution;  ///< organ cells along its length
};
constexpr std::array<MeshCase, 3> kCases{{{"organ 1k", 10}, {"organ 10k", 30}, {"organ 100k", 93}}};

/// Mean and standard deviation by Welford's update (the histogram has no second moment).
class Moments {
 public:
  void add(double x) {
    ++n_;
    const double delta = x - mean_;
    mean_ += delta / static_cast<double>(n_);
    m2_ += delta * (x - mean_);
  }
  [[nodiscard]] double mean() const { return mean_; }
  [[nodiscard]] double sd() const { return n_ > 1 ? std::sqrt(m2_ / static_cast<double>(n_ - 1)) : 0.0; }

 private:
  std::uint64_t n_ = 0;
  double mean_ = 0.0, m2_ = 0.0;
};

struct Timings {
  LatencyHistogram histogram;
  Moments moments;
  void add(Nanos ns) {
    histogram.record(ns);
    moments.add(static_cast<double>(ns));
  }
};

struct Row {
  const char* name = "";
  std::size_t triangles = 0;
  double contact_fraction = 0.0, sweeps_per_update = 0.0, quality = 0.0;
  Timings update, refit;
};

std::vector<Row>& rows() {
  static std::vector<Row> r;
  return r;
}

/// The organ moved by a travelling wave at simulation step `step`.
void deform(const std::vector<Vec3>& rest, double size, int step, std::vector<Vec3>& out) {
  const Vec3 k = Vec3(1.0, 0.6, 0.3).normalized() * (2.0 * std::numbers::pi / size);
  const Vec3 along = Vec3(0.2, 0.3, 1.0).normalized();
  const double phase = 0.05 * step;  // 0.05 rad per 10 ms: up to 0.2 mm per step
  for (std::size_t i = 0; i < rest.size(); ++i)
    out[i] = rest[i] + 0.02 * size * std::sin(k.dot(rest[i]) + phase) * along;
}

/// Points of a closed loop around the organ (rays from its centre, which is inside) with the
/// outward direction there, about 0.1 mm apart.
struct PathPoint {
  Vec3 surface, outward;
};
std::vector<PathPoint> loop_around(const TriangleBvh& tree) {
  std::vector<PathPoint> out;
  std::vector<RayHit> hits;
  const int n = 6000;
  for (int i = 0; i < n; ++i) {
    const double a = 2.0 * std::numbers::pi * i / n;
    const Vec3 d = Vec3(std::cos(a), 0.8 * std::sin(a), 0.3 * std::sin(3.0 * a)).normalized();
    tree.raycast(Vec3::Zero(), d, std::numeric_limits<double>::infinity(), hits);
    if (!hits.empty()) out.push_back({hits.back().point, d});
  }
  return out;
}

Nanos since(Clock::time_point t0) {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - t0).count();
}

void BM_HapticUpdate(benchmark::State& state) {
  const MeshCase& c = kCases[static_cast<std::size_t>(state.range(0))];
  const mesh::TriMesh organ = mesh::organ(kOrganLength, c.resolution);
  const double size = organ.bounds().size().norm();
  std::vector<Vec3> x = organ.vertices;
  TriangleBvh tree(x, organ.triangles);
  const std::vector<PathPoint> path = loop_around(tree);
  const BvhSurfaceQuery surface(tree);

  ProxyParams params;
  params.radius = 0.001;
  params.stiffness = 800.0;
  params.damping = 0.2;
  params.static_friction = 0.5;
  params.kinetic_friction = 0.3;
  validate_proxy_params(params);
  ProxyState proxy = make_proxy_state(path.front().surface + 0.01 * path.front().outward);

  Row row;
  row.name = c.name;
  row.triangles = organ.triangles.size();
  std::uint64_t contacts = 0, sweeps = 0, recorded = 0;
  int update = 0, step = 0;
  Vec3 last_goal = proxy.position;
  // One haptic update; returns its time.
  auto next_period = Clock::now();
  auto haptic_update = [&]() -> Nanos {
    next_period += std::chrono::microseconds(1000);
    std::this_thread::sleep_until(next_period);
    const PathPoint& p = path[static_cast<std::size_t>(update) % path.size()];
    const double depth = 0.002 + 0.004 * std::sin(2.0 * std::numbers::pi * update * kHapticDt / 1.5);
    const Vec3 goal = p.surface - depth * p.outward;
    const Vec3 goal_velocity = (goal - last_goal) / kHapticDt;
    last_goal = goal;
    const auto t0 = Clock::now();
    const ProxyResult r = update_proxy(params, proxy, goal, goal_velocity, kHapticDt, surface);
    const Nanos ns = since(t0);
    benchmark::DoNotOptimize(r.force);
    if (update >= kWarmUpUpdates) {
      contacts += r.in_contact ? 1 : 0;
      sweeps += static_cast<std::uint64_t>(r.sweeps);
      ++recorded;
    }
    ++update;
    if (update % kUpdatesPerStep == 0) {
      // A simulation step ends: the surface moves (not timed) and the tree is refitted.
      deform(organ.vertices, size, ++step, x);
      const auto t_refit = Clock::now();
      tree.refit(x);
      const Nanos refit_ns = since(t_refit);
      if (update > kWarmUpUpdates) row.refit.add(refit_ns);
    }
    return ns;
  };
  while (update < kWarmUpUpdates) (void)haptic_update();
  for (auto _ : state) {
    const Nanos ns = haptic_update();
    row.update.add(ns);
    state.SetIterationTime(1e-9 * static_cast<double>(ns));
  }
  row.contact_fraction = static_cast<double>(contacts) / static_cast<double>(recorded);
  row.sweeps_per_update = static_cast<double>(sweeps) / static_cast<double>(recorded);
  row.quality = tree.quality();
  state.counters["triangles"] = static_cast<double>(row.triangles);
  state.counters["p50_us"] = 1e-3 * static_cast<double>(row.update.histogram.percentile(50));
  state.counters["p99_us"] = 1e-3 * static_cast<double>(row.update.histogram.percentile(99));
  state.counters["sd_us"] = 1e-3 * row.update.moments.sd();
  state.counters["refit_p50_us"] = 1e-3 * static_cast<double>(row.refit.histogram.percentile(50));
  state.counters["contact"] = row.contact_fraction;
  state.SetLabel(c.name);
  rows().push_back(std::move(row));
}

BENCHMARK(BM_HapticUpdate)->DenseRange(0, 2)->Iterations(kUpdates)->UseManualTime()->Unit(benchmark::kMicrosecond);

void print_table() {
  const auto us = [](Nanos ns) { return 1e-3 * static_cast<double>(ns); };
  std::printf("\n| mesh | triangles | in contact | sweeps/update | what | p50 µs | p99 µs | p99.9 µs | max µs | "
              "mean µs | SD µs |\n|---|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|\n");
  for (const Row& r : rows()) {
    for (const auto& [what, t] : {std::pair<const char*, const Timings*>{"haptic update", &r.update},
                                  std::pair<const char*, const Timings*>{"refit (every 10th)", &r.refit}}) {
      const LatencyHistogram& h = t->histogram;
      std::printf("| %s | %zu | %.0f %% | %.2f | %s | %.2f | %.2f | %.2f | %.1f | %.2f | %.2f |\n", r.name,
                  r.triangles, 100.0 * r.contact_fraction, r.sweeps_per_update, what, us(h.percentile(50)),
                  us(h.percentile(99)), us(h.percentile(99.9)), us(h.max()), 1e-3 * t->moments.mean(),
                  1e-3 * t->moments.sd());
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  print_table();
  return 0;
}
