// Smoothing weights for the labelled-image domain, kept out of the CGAL translation unit.
#include <algorithm>
#include <cmath>

#include "imaging/label_mesher.hpp"

namespace tactus::imaging::detail {
namespace {

/// One pass of a 1D Gaussian along `axis` over the box [lo, hi), in place (clamped at the box).
void blur_axis(std::vector<float>& f, const std::array<std::size_t, 3>& size, const std::array<std::size_t, 3>& lo,
               const std::array<std::size_t, 3>& hi, int axis, const std::vector<float>& kernel) {
  const auto radius = static_cast<std::ptrdiff_t>(kernel.size() / 2);
  const std::size_t stride = axis == 0 ? 1 : axis == 1 ? size[0] : size[0] * size[1];
  const std::size_t n = hi[axis] - lo[axis];
  std::vector<float> line(n), out(n);
  const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
  for (std::size_t u = lo[a1]; u < hi[a1]; ++u) {
    for (std::size_t v = lo[a2]; v < hi[a2]; ++v) {
      std::array<std::size_t, 3> p{};
      p[axis] = lo[axis];
      p[a1] = u;
      p[a2] = v;
      const std::size_t base = p[0] + size[0] * (p[1] + size[1] * p[2]);
      for (std::size_t t = 0; t < n; ++t) line[t] = f[base + t * stride];
      for (std::size_t t = 0; t < n; ++t) {
        float sum = 0.0f;
        for (std::ptrdiff_t r = -radius; r <= radius; ++r) {
          const std::ptrdiff_t s = std::clamp(static_cast<std::ptrdiff_t>(t) + r, std::ptrdiff_t{0},
                                              static_cast<std::ptrdiff_t>(n) - 1);
          sum += kernel[static_cast<std::size_t>(r + radius)] * line[static_cast<std::size_t>(s)];
        }
        out[t] = sum;
      }
      for (std::size_t t = 0; t < n; ++t) f[base + t * stride] = out[t];
    }
  }
}

}  // namespace

std::vector<std::uint8_t> label_weights(const std::vector<std::uint8_t>& compact, const std::array<std::size_t, 3>& size,
                                        const Vec3& voxel_units, int label_count, double sigma) {
  // One Gaussian in space: along an axis of longer voxels it spans fewer of them.
  std::array<std::vector<float>, 3> kernels;
  std::array<std::size_t, 3> radii{};
  for (int a = 0; a < 3; ++a) {
    const double s = sigma / voxel_units[a];
    radii[a] = static_cast<std::size_t>(std::ceil(3.0 * s));
    auto& kernel = kernels[a];
    kernel.resize(2 * radii[a] + 1);
    float total = 0.0f;
    for (std::size_t i = 0; i < kernel.size(); ++i) {
      const double x = static_cast<double>(i) - static_cast<double>(radii[a]);
      kernel[i] = static_cast<float>(std::exp(-0.5 * x * x / (s * s)));
      total += kernel[i];
    }
    for (float& k : kernel) k /= total;
  }

  std::vector<float> best(compact.size(), 0.0f), indicator(compact.size());
  for (int label = 0; label < label_count; ++label) {
    // Only the label's bounding box grown by the kernel radius: elsewhere its smoothed
    // indicator is 0 and cannot raise the maximum.
    std::array<std::size_t, 3> lo{size}, hi{0, 0, 0};
    for (std::size_t k = 0, v = 0; k < size[2]; ++k)
      for (std::size_t j = 0; j < size[1]; ++j)
        for (std::size_t i = 0; i < size[0]; ++i, ++v)
          if (compact[v] == label) {
            const std::array<std::size_t, 3> p{i, j, k};
            for (int a = 0; a < 3; ++a) {
              lo[a] = std::min(lo[a], p[a]);
              hi[a] = std::max(hi[a], p[a] + 1);
            }
          }
    if (hi[0] == 0) continue;
    for (int a = 0; a < 3; ++a) {
      lo[a] = lo[a] > radii[a] ? lo[a] - radii[a] : 0;
      hi[a] = std::min(size[a], hi[a] + radii[a]);
    }
    for (std::size_t k = lo[2]; k < hi[2]; ++k)
      for (std::size_t j = lo[1]; j < hi[1]; ++j) {
        const std::size_t row = size[0] * (j + size[1] * k);
        for (std::size_t i = lo[0]; i < hi[0]; ++i) indicator[row + i] = compact[row + i] == label ? 255.0f : 0.0f;
      }
    for (int axis = 0; axis < 3; ++axis)
      if (radii[axis] > 0) blur_axis(indicator, size, lo, hi, axis, kernels[axis]);
    for (std::size_t k = lo[2]; k < hi[2]; ++k)
      for (std::size_t j = lo[1]; j < hi[1]; ++j) {
        const std::size_t row = size[0] * (j + size[1] * k);
        for (std::size_t i = lo[0]; i < hi[0]; ++i) best[row + i] = std::max(best[row + i], indicator[row + i]);
      }
  }
  std::vector<std::uint8_t> weights(compact.size());
  for (std::size_t v = 0; v < compact.size(); ++v)
    weights[v] = static_cast<std::uint8_t>(std::clamp(std::lround(best[v]), 0L, 255L));
  return weights;
}

}  // namespace tactus::imaging::detail
