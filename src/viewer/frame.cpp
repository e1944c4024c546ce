#include "viewer/frame.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace tactus::viewer {

Aabb frame_bounds(const FrameView& frame) {
  Aabb box;
  box.min = Vec3::Constant(std::numeric_limits<double>::infinity());
  box.max = -box.min;
  for (const SurfaceView& s : frame.surfaces)
    for (const Vec3& p : s.positions) {
      box.min = box.min.cwiseMin(p);
      box.max = box.max.cwiseMax(p);
    }
  for (const SphereView& s : frame.spheres) {
    box.min = box.min.cwiseMin(s.centre - Vec3::Constant(s.radius));
    box.max = box.max.cwiseMax(s.centre + Vec3::Constant(s.radius));
  }
  if (!(box.min.array() <= box.max.array()).all()) box = Aabb{Vec3::Constant(-0.05), Vec3::Constant(0.05)};
  return box;
}

Colour pressure_colour(double fraction) {
  static const std::array<Colour, 5> ramp = {Colour(0.1, 0.2, 0.9), Colour(0.0, 0.8, 0.9), Colour(0.1, 0.85, 0.2),
                                             Colour(1.0, 0.9, 0.0), Colour(1.0, 0.1, 0.05)};
  const double x = std::clamp(std::isfinite(fraction) ? fraction : 0.0, 0.0, 1.0) * (ramp.size() - 1);
  const auto i = std::min<std::size_t>(static_cast<std::size_t>(x), ramp.size() - 2);
  const double w = x - static_cast<double>(i);
  return (1.0 - w) * ramp[i] + w * ramp[i + 1];
}

}  // namespace tactus::viewer
