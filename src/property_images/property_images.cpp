#include "property_images/property_images.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>

#include "contact/bvh.hpp"
#include "mesh/half_edge.hpp"

namespace tactus::property_images {

namespace {

float load(const float& x) { return std::atomic_ref<const float>(x).load(std::memory_order_relaxed); }
void store(float& x, float v) { std::atomic_ref<float>(x).store(v, std::memory_order_relaxed); }

/// The two image axes of a view along `axis`, in right-handed order.
std::pair<int, int> image_axes(int axis) { return {(axis + 1) % 3, (axis + 2) % 3}; }

/// Distance from the view's face to `p` along its ray.
double depth_of(const Aabb& box, const View& v, const Vec3& p) {
  return v.sign > 0 ? box.max[v.axis] - p[v.axis] : p[v.axis] - box.min[v.axis];
}

}  // namespace

void validate(const SurfaceProperties& p, const SourceLocation& where) {
  constexpr std::array<double, kChannelCount> kMax = {kMaxStiffness,          kMaxFriction,           kMaxFriction,
                                                      kMaxDamping,            kMaxRoughnessAmplitude, kMaxRoughnessWavelength,
                                                      kMaxYoungModulus,       kMaxPoissonRatio};
  for (int c = 0; c < kChannelCount; ++c) {
    const double v = p.values[c];
    if (!std::isfinite(v) || v < 0.0 || v > kMax[c])
      throw InputError(where, fmt::format("{} must be in [0, {:g}], got {:g}", kChannelNames[c], kMax[c], v));
  }
  if (p[Channel::kinetic_friction] > p[Channel::static_friction])
    throw InputError(where, fmt::format("kinetic_friction {:g} exceeds static_friction {:g}",
                                        p[Channel::kinetic_friction], p[Channel::static_friction]));
  if (p[Channel::roughness_amplitude] > 0.0 && p[Channel::roughness_wavelength] <= 0.0)
    throw InputError(where, "a roughness_amplitude needs a roughness_wavelength > 0");
}

PropertyImages::PropertyImages(const Aabb& box, double pixel, std::uint64_t mesh_hash, const SurfaceProperties& base,
                               std::array<View, kViewCount> views)
    : box_(box), pixel_(pixel), mesh_hash_(mesh_hash), base_(base), views_(std::move(views)) {}

PropertyImages PropertyImages::build(const mesh::TriMesh& surface, int resolution, const SurfaceProperties& base,
                                     const SourceLocation& where) {
  if (resolution < 2 || resolution > kMaxResolution)
    throw InputError(where, fmt::format("resolution must be in [2, {}], got {}", kMaxResolution, resolution));
  validate(base, where);
  if (surface.triangles.empty()) throw InputError(where, "property images need a surface; the mesh has no triangles");
  const mesh::HalfEdgeMesh topology(surface);  // throws on a non-manifold surface
  if (!topology.closed())
    throw InputError(where, fmt::format("property images need a closed surface; this one has {} open edges",
                                        topology.num_boundary_half_edges()));

  Aabb box = surface.bounds();
  const double longest = box.size().maxCoeff();
  if (!(longest > 0.0)) throw InputError(where, "property images need a surface with a non-zero extent");
  const double pixel = longest / resolution;
  box.min.array() -= pixel;
  box.max.array() += pixel;

  const contact::TriangleBvh tree(surface.vertices, surface.triangles);
  std::array<View, kViewCount> views;
  std::vector<contact::RayHit> hits;
  for (int i = 0; i < kViewCount; ++i) {
    View& v = views[i];
    v.axis = i / 2;
    v.sign = i % 2 == 0 ? 1 : -1;
    std::tie(v.u_axis, v.v_axis) = image_axes(v.axis);
    const Vec3 size = box.size();
    v.width = static_cast<int>(std::ceil(size[v.u_axis] / pixel));
    v.height = static_cast<int>(std::ceil(size[v.v_axis] / pixel));
    const auto n = static_cast<std::size_t>(v.width) * static_cast<std::size_t>(v.height);
    v.depth.assign(n, static_cast<float>(kInf));
    v.values.resize(n * kChannelCount);
    for (std::size_t p = 0; p < n; ++p)
      for (int c = 0; c < kChannelCount; ++c) v.values[p * kChannelCount + c] = static_cast<float>(base.values[c]);
    Vec3 direction = Vec3::Zero();
    direction[v.axis] = -v.sign;
    const double reach = size[v.axis];
    for (int row = 0; row < v.height; ++row) {
      for (int col = 0; col < v.width; ++col) {
        Vec3 origin;
        origin[v.axis] = v.sign > 0 ? box.max[v.axis] : box.min[v.axis];
        origin[v.u_axis] = box.min[v.u_axis] + (col + 0.5) * pixel;
        origin[v.v_axis] = box.min[v.v_axis] + (row + 0.5) * pixel;
        tree.raycast(origin, direction, reach, hits);
        if (!hits.empty()) v.depth[static_cast<std::size_t>(row) * v.width + col] = static_cast<float>(hits.front().t);
      }
    }
  }
  return PropertyImages(box, pixel, surface.content_hash(), base, std::move(views));
}

std::size_t PropertyImages::bytes() const {
  std::size_t b = 0;
  for (const View& v : views_) b += (v.depth.size() + v.values.size()) * sizeof(float);
  return b;
}

Vec3 PropertyImages::surface_point(int view, int column, int row) const {
  const View& v = views_[view];
  Vec3 p;
  const double d = v.depth[static_cast<std::size_t>(row) * v.width + column];
  p[v.axis] = v.sign > 0 ? box_.max[v.axis] - d : box_.min[v.axis] + d;
  p[v.u_axis] = box_.min[v.u_axis] + (column + 0.5) * pixel_;
  p[v.v_axis] = box_.min[v.v_axis] + (row + 0.5) * pixel_;
  return p;
}

Lookup PropertyImages::lookup(const Vec3& point, const Vec3& normal) const {
  Lookup out;
  out.properties = base_;
  if (views_[0].width == 0) return out;
  // Views in order of how squarely they face the normal.
  std::array<std::pair<double, int>, kViewCount> order;
  for (int i = 0; i < kViewCount; ++i) order[i] = {-views_[i].sign * normal[views_[i].axis], i};
  std::sort(order.begin(), order.end());
  // A surface seen at up to about 55° from a view changes depth by up to √2 pixels per pixel,
  // so a pixel beside the point's may lie that much deeper: two pixels of tolerance.
  const double tolerance = 2.0 * pixel_;
  for (const auto& [facing, index] : order) {
    if (facing >= 0.0) break;  // the view looks at the back of this surface
    const View& v = views_[index];
    const double d = depth_of(box_, v, point);
    const double fu = (point[v.u_axis] - box_.min[v.u_axis]) / pixel_ - 0.5;
    const double fv = (point[v.v_axis] - box_.min[v.v_axis]) / pixel_ - 0.5;
    if (!std::isfinite(fu) || !std::isfinite(fv)) return out;
    const double cu = std::clamp(fu, 0.0, v.width - 1.0), cv = std::clamp(fv, 0.0, v.height - 1.0);
    const int u0 = std::min(static_cast<int>(cu), v.width - 1), v0 = std::min(static_cast<int>(cv), v.height - 1);
    const int u1 = std::min(u0 + 1, v.width - 1), v1 = std::min(v0 + 1, v.height - 1);
    const double au = cu - u0, av = cv - v0;
    const std::array<std::pair<std::size_t, double>, 4> taps = {{
        {static_cast<std::size_t>(v0) * v.width + u0, (1 - au) * (1 - av)},
        {static_cast<std::size_t>(v0) * v.width + u1, au * (1 - av)},
        {static_cast<std::size_t>(v1) * v.width + u0, (1 - au) * av},
        {static_cast<std::size_t>(v1) * v.width + u1, au * av},
    }};
    std::array<double, kChannelCount> sum{};
    double weight = 0.0;
    for (const auto& [pixel, w] : taps) {
      if (w <= 0.0 || !(std::abs(v.depth[pixel] - d) <= tolerance)) continue;
      for (int c = 0; c < kChannelCount; ++c) sum[c] += w * load(v.values[pixel * kChannelCount + c]);
      weight += w;
    }
    if (weight <= 1e-9) continue;  // the point is hidden from this view
    for (int c = 0; c < kChannelCount; ++c) out.properties.values[c] = sum[c] / weight;
    out.view = index;
    return out;
  }
  return out;
}

PropertyImages::Height PropertyImages::roughness_height(const Vec3& point, int view, double amplitude,
                                                        double wavelength) const {
  Height out;
  if (view < 0 || amplitude <= 0.0 || wavelength <= 0.0) return out;
  const View& v = views_[view];
  const double k = 2.0 * std::numbers::pi / wavelength;
  const double su = std::sin(k * point[v.u_axis]), cu = std::cos(k * point[v.u_axis]);
  const double sv = std::sin(k * point[v.v_axis]), cv = std::cos(k * point[v.v_axis]);
  out.h = amplitude * su * sv;
  out.gradient[v.u_axis] = amplitude * k * cu * sv;
  out.gradient[v.v_axis] = amplitude * k * su * cv;
  return out;
}

std::size_t PropertyImages::paint(const Vec3& center, double radius, const SurfaceProperties& values,
                                  ChannelMask mask) {
  std::size_t written = 0;
  if (!(radius > 0.0) || !center.allFinite()) return 0;
  for (int i = 0; i < kViewCount; ++i) {
    View& v = views_[i];
    // Only the pixels whose column and row can be within the brush.
    const auto range = [&](int axis, int count) {
      const double lo = (center[axis] - radius - box_.min[axis]) / pixel_ - 0.5;
      const double hi = (center[axis] + radius - box_.min[axis]) / pixel_ - 0.5;
      return std::pair{std::clamp(static_cast<int>(std::ceil(lo)), 0, count),
                       std::clamp(static_cast<int>(std::floor(hi)) + 1, 0, count)};
    };
    const auto [c0, c1] = range(v.u_axis, v.width);
    const auto [r0, r1] = range(v.v_axis, v.height);
    for (int row = r0; row < r1; ++row) {
      for (int col = c0; col < c1; ++col) {
        const std::size_t pixel = static_cast<std::size_t>(row) * v.width + col;
        if (!std::isfinite(v.depth[pixel]) || (surface_point(i, col, row) - center).norm() > radius) continue;
        for (int c = 0; c < kChannelCount; ++c)
          if (mask & (1u << c)) store(v.values[pixel * kChannelCount + c], static_cast<float>(values.values[c]));
        ++written;
      }
    }
  }
  return written;
}

}  // namespace tactus::property_images
