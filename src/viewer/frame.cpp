#include "viewer/frame.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cctype>
#include <limits>
#include <string_view>
#include <utility>

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

double ArrowView::length() const {
  const double l = force.norm() * length_per_newton;
  return std::isfinite(l) ? std::min(l, max_length) : 0.0;
}

Colour body_colour(const std::string& name, std::size_t index) {
  std::string lower(name);
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
  // First match wins: "femoral_artery" is an artery before it is anything else.
  static const std::pair<std::string_view, Colour> by_name[] = {
      {"artery", Colour(0.85, 0.12, 0.12)},   {"vein", Colour(0.2, 0.3, 0.85)},
      {"nerve", Colour(0.95, 0.85, 0.2)},     {"fascia", Colour(0.82, 0.8, 0.92)},
      {"ligament", Colour(0.6, 0.82, 0.78)},  {"tendon", Colour(0.6, 0.82, 0.78)},
      {"skin", Colour(0.93, 0.76, 0.66)},     {"fat", Colour(0.98, 0.88, 0.55)},
      {"muscle", Colour(0.72, 0.36, 0.32)},   {"tissue", Colour(0.72, 0.36, 0.32)},
      {"femur", Colour(0.95, 0.93, 0.85)},    {"bone", Colour(0.95, 0.93, 0.85)},
      {"hip", Colour(0.95, 0.93, 0.85)},      {"liver", Colour(0.55, 0.22, 0.18)},
      {"nodule", Colour(0.85, 0.45, 0.55)},
  };
  for (const auto& [key, colour] : by_name)
    if (lower.find(key) != std::string::npos) return colour;
  static const Colour palette[] = {Colour(0.93, 0.76, 0.66), Colour(0.72, 0.36, 0.32), Colour(0.62, 0.68, 0.82),
                                   Colour(0.85, 0.78, 0.52)};
  return palette[index % std::size(palette)];
}

std::vector<Colour> body_colours(const std::vector<std::string>& names) {
  std::vector<Colour> out;
  for (std::size_t i = 0; i < names.size(); ++i) {
    const Colour base = body_colour(names[i], i);
    const auto repeats = std::count_if(names.begin(), names.begin() + static_cast<std::ptrdiff_t>(i),
                                       [&](const std::string& n) { return body_colour(n, 0).isApprox(base); });
    out.push_back(base * std::pow(0.8, static_cast<double>(repeats)));
  }
  return out;
}

}  // namespace tactus::viewer
