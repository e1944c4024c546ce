// Haptic property images (seed 001, second chapter) on the room scene's objects, against the
// two representations the seed argues against: properties per vertex (detail bound to the
// mesh) and a voxel grid of the same detail (N³ cells). Per object and resolution: the bytes
// of each, the images' build time (six ray-cast depth images), and the lookup time at the
// contact (p50, p99 over 20,000 surface points with their normals, each timed on its own).
// Run in Release: bench/bench_property_images [MESH_FOLDER]; results in docs/property-images.md.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "mesh/io/mesh_io.hpp"
#include "property_images/property_images.hpp"

namespace {

using namespace tactus;
using Clock = std::chrono::steady_clock;

double seconds(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); }

}  // namespace

int main(int argc, char** argv) {
  const std::filesystem::path folder =
      argc > 1 ? std::filesystem::path(argv[1]) : std::filesystem::path(TACTUS_BENCH_ROOM_MESHES);
  property_images::SurfaceProperties base;
  base[property_images::Channel::stiffness] = 800.0;
  std::printf("%-8s %9s %5s %11s %11s %13s %9s %8s %8s\n", "object", "triangles", "res", "images kB", "vertex kB",
              "voxel grid kB", "build ms", "p50 ns", "p99 ns");
  for (const char* name : {"table", "kettle", "teapot", "vase", "dragon", "bunny"}) {
    const mesh::TriMesh surface = *mesh::read_mesh(folder / (std::string(name) + ".obj")).surface;
    // Surface points with their normals: the triangles' centroids, picked at random.
    std::mt19937 rng(7);
    std::uniform_int_distribution<std::size_t> pick(0, surface.triangles.size() - 1);
    std::vector<std::pair<Vec3, Vec3>> points;
    for (int i = 0; i < 20000; ++i) {
      const std::size_t t = pick(rng);
      const auto& f = surface.triangles[t];
      points.emplace_back((surface.vertices[f[0]] + surface.vertices[f[1]] + surface.vertices[f[2]]) / 3.0,
                          surface.face_normal(t));
    }
    for (const int resolution : {128, 256, 512}) {
      const auto t0 = Clock::now();
      const auto images = property_images::PropertyImages::build(surface, resolution, base, {name, {}, {}, {}});
      const auto t1 = Clock::now();
      std::vector<double> times;
      double sink = 0.0;
      int unseen = 0;
      for (const auto& [p, n] : points) {
        const auto a = Clock::now();
        const auto l = images.lookup(p, n);
        const auto b = Clock::now();
        sink += l.properties[property_images::Channel::stiffness];
        unseen += l.view < 0 ? 1 : 0;
        times.push_back(1e9 * seconds(a, b));
      }
      std::sort(times.begin(), times.end());
      const Vec3 size = images.box().size();
      const double cells = std::ceil(size.x() / images.pixel()) * std::ceil(size.y() / images.pixel()) *
                           std::ceil(size.z() / images.pixel());
      const double channel_bytes = property_images::kChannelCount * sizeof(float);
      std::printf("%-8s %9zu %5d %11.0f %11.0f %13.0f %9.1f %8.0f %8.0f   (%d of 20000 seen by no view; %.0f)\n", name,
                  surface.triangles.size(), resolution, images.bytes() / 1e3,
                  surface.vertices.size() * channel_bytes / 1e3, cells * channel_bytes / 1e3, 1e3 * seconds(t0, t1),
                  times[times.size() / 2], times[times.size() * 99 / 100], unseen, sink / 20000.0);
    }
  }
  return 0;
}
