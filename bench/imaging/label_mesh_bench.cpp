// Meshing a 256³ label image with 5 labels (0.5 mm voxels, a 128 mm cube) to about 50k
// tetrahedra: an organ (ellipsoid) holding a tumour (sphere) and a vessel (cylinder), a
// second small organ, and a slab of muscle below. Arguments: smoothing sigma in tenths of
// a voxel (0 or 10). Counters: tets; the time is the whole mesh_label_image call.
#include <benchmark/benchmark.h>

#include <cmath>
#include <filesystem>

#include "imaging/label_mesher.hpp"

namespace {

using namespace tactus;

imaging::LabelImage five_labels() {
  constexpr std::size_t n = 256;
  const double h = 0.5e-3;
  imaging::LabelImage image;
  image.size = {n, n, n};
  image.spacing = Vec3::Constant(h);
  image.labels.resize(n * n * n);
  for (std::size_t k = 0; k < n; ++k)
    for (std::size_t j = 0; j < n; ++j)
      for (std::size_t i = 0; i < n; ++i) {
        const Vec3 p = Vec3(static_cast<double>(i), static_cast<double>(j), static_cast<double>(k)) * h;
        const Vec3 organ = (p - Vec3(0.060, 0.064, 0.070)).cwiseQuotient(Vec3(0.045, 0.035, 0.030));
        int label = 0;
        if (p.z() < 0.030 && p.z() > 0.008) label = 5;                                        // muscle slab
        if ((p - Vec3(0.105, 0.100, 0.060)).norm() < 0.015) label = 4;                        // small organ
        if (organ.squaredNorm() < 1.0) label = 1;                                             // organ
        if ((p - Vec3(0.070, 0.060, 0.075)).norm() < 0.012) label = 2;                        // tumour
        if (std::hypot(p.y() - 0.075, p.z() - 0.062) < 0.004 && organ.squaredNorm() < 1.3) label = 3;  // vessel
        image.labels[image.index(i, j, k)] = label;
      }
  return image;
}

void BM_MeshLabels256(benchmark::State& state) {
  static const imaging::LabelImage image = five_labels();
  imaging::LabelMeshOptions o;
  o.cell_size = 4e-3;
  o.cell_size_by_label[3] = 1.5e-3;  // the vessel
  o.smooth_sigma = static_cast<double>(state.range(0)) / 10.0;
  o.progress = false;
  std::size_t tets = 0;
  for (auto _ : state) {
    const mesh::TetMesh m = imaging::mesh_label_image(image, o);
    tets = m.tets.size();
    benchmark::DoNotOptimize(tets);
  }
  state.counters["tets"] = static_cast<double>(tets);
}
BENCHMARK(BM_MeshLabels256)->Arg(0)->Arg(10)->Unit(benchmark::kSecond)->Iterations(1)->Repetitions(3);

/// Reading the same image from a .nii.gz (int16 voxels, about 100 KB compressed).
void BM_ReadNiftiGz256(benchmark::State& state) {
  const auto file = std::filesystem::temp_directory_path() / "tactus_label_bench.nii.gz";
  imaging::write_nifti(file, five_labels());
  state.counters["bytes"] = static_cast<double>(std::filesystem::file_size(file));
  for (auto _ : state) benchmark::DoNotOptimize(imaging::read_nifti(file).labels.data());
  std::filesystem::remove(file);
}
BENCHMARK(BM_ReadNiftiGz256)->Unit(benchmark::kSecond)->Iterations(1)->Repetitions(3);

}  // namespace

BENCHMARK_MAIN();
