#include "haptics/trajectory.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <type_traits>
#include <utility>

namespace tactus::haptics {
namespace {

// ---- waypoints ------------------------------------------------------------------------------

/// Time inside the path: loops wrap with period = last time; negative times count as 0.
double waypoint_local_time(const WaypointsPath& p, double t) {
  t = std::max(t, 0.0);
  const double period = p.points.back().time;
  if (p.loop && period > 0.0 && t >= period) t = std::fmod(t, period);
  return t;
}

/// Index i of the segment [points[i], points[i+1]] that holds t (right-continuous), or -1
/// before the first point and size-1 at or after the last.
std::ptrdiff_t waypoint_segment(const WaypointsPath& p, double t) {
  const auto after = std::upper_bound(p.points.begin(), p.points.end(), t,
                                      [](double time, const Waypoint& w) { return time < w.time; });
  return (after - p.points.begin()) - 1;
}

Vec3 waypoints_position(const WaypointsPath& p, double t) {
  if (p.points.empty()) return Vec3::Zero();
  t = waypoint_local_time(p, t);
  const std::ptrdiff_t i = waypoint_segment(p, t);
  if (i < 0) return p.points.front().position;
  if (i + 1 >= static_cast<std::ptrdiff_t>(p.points.size())) return p.points.back().position;
  const Waypoint& a = p.points[static_cast<std::size_t>(i)];
  const Waypoint& b = p.points[static_cast<std::size_t>(i) + 1];
  const double s = (t - a.time) / (b.time - a.time);
  return a.position + s * (b.position - a.position);
}

Vec3 waypoints_direction(const WaypointsPath& p, double t) {
  if (p.points.empty()) return Vec3(0, 0, -1);
  t = waypoint_local_time(p, t);
  const std::ptrdiff_t i = waypoint_segment(p, t);
  if (i < 0) return p.points.front().direction;
  if (i + 1 >= static_cast<std::ptrdiff_t>(p.points.size())) return p.points.back().direction;
  const Waypoint& a = p.points[static_cast<std::size_t>(i)];
  const Waypoint& b = p.points[static_cast<std::size_t>(i) + 1];
  const double s = (t - a.time) / (b.time - a.time);
  const Vec3 d = a.direction + s * (b.direction - a.direction);
  // Opposite directions blend through zero: keep the earlier one until past the middle.
  return d.norm() > 1e-9 ? Vec3(d.normalized()) : (s < 0.5 ? a.direction : b.direction);
}

Vec3 waypoints_velocity(const WaypointsPath& p, double t) {
  if (p.points.empty()) return Vec3::Zero();
  t = waypoint_local_time(p, t);
  const std::ptrdiff_t i = waypoint_segment(p, t);
  if (i < 0 || i + 1 >= static_cast<std::ptrdiff_t>(p.points.size())) return Vec3::Zero();
  const Waypoint& a = p.points[static_cast<std::size_t>(i)];
  const Waypoint& b = p.points[static_cast<std::size_t>(i) + 1];
  return (b.position - a.position) / (b.time - a.time);
}

double waypoints_duration(const WaypointsPath& p) {
  if (p.points.empty()) return 0.0;
  const double last = p.points.back().time;
  return p.loop && last > 0.0 ? kInf : last;
}

// ---- raster ---------------------------------------------------------------------------------

/// Scan lines at y_i = min.y + min(i·spacing, height), i = 0..gaps: the last line lies on
/// max.y even when the height is not a multiple of the spacing, so all four corners are
/// visited. Line i runs +x for even i, −x for odd i; short moves in +y join the lines.
struct RasterLayout {
  double width = 0.0;
  double height = 0.0;
  double spacing = 0.0;
  double gaps = 0.0;  ///< number of connecting moves (lines − 1)
  double length = 0.0;

  explicit RasterLayout(const RasterPath& p) {
    width = std::max(p.max.x() - p.min.x(), 0.0);
    height = std::max(p.max.y() - p.min.y(), 0.0);
    spacing = p.spacing > 0.0 ? p.spacing : std::max(height, 1.0);
    // The small tolerance keeps an exact multiple from adding a zero-length last gap.
    gaps = height > 0.0 ? std::max(std::ceil(height / spacing - 1e-9), 1.0) : 0.0;
    length = (gaps + 1.0) * width + height;
  }
  [[nodiscard]] double line_y(const RasterPath& p, double i) const {
    return p.min.y() + std::min(i * spacing, height);
  }
  /// Arc length at which line i starts.
  [[nodiscard]] double line_start(const RasterPath& p, double i) const {
    return i * width + (line_y(p, i) - p.min.y());
  }
};

/// Position and unit direction of travel at arc length s ∈ [0, length].
std::pair<Vec3, Vec3> raster_at_arc(const RasterPath& p, const RasterLayout& r, double s) {
  s = std::clamp(s, 0.0, r.length);
  double line = r.gaps;
  if (s < r.line_start(p, r.gaps)) {
    line = std::clamp(std::floor(s / (r.width + r.spacing)), 0.0, r.gaps - 1.0);
    // Rounding in the division can land one line off; one correction step each way suffices.
    if (s < r.line_start(p, line) && line > 0.0) line -= 1.0;
    if (line + 1.0 < r.gaps && s >= r.line_start(p, line + 1.0)) line += 1.0;
  }
  const bool forward = std::fmod(line, 2.0) == 0.0;
  const double y = r.line_y(p, line);
  const double local = std::max(s - r.line_start(p, line), 0.0);
  if (local < r.width || line == r.gaps) {
    const double along = std::min(local, r.width);
    const double x = forward ? p.min.x() + along : p.max.x() - along;
    return {Vec3(x, y, p.z), Vec3(forward ? 1.0 : -1.0, 0.0, 0.0)};
  }
  const double x = forward ? p.max.x() : p.min.x();
  const double rise = std::min(local - r.width, r.line_y(p, line + 1.0) - y);
  return {Vec3(x, y + rise, p.z), Vec3(0.0, 1.0, 0.0)};
}

// The approach (straight down from `approach` above the first line's start) is arc length
// [0, approach); the scan follows it.
Vec3 raster_position(const RasterPath& p, double t) {
  const RasterLayout r(p);
  const double s = p.speed > 0.0 ? std::max(t, 0.0) * p.speed : 0.0;
  if (s < p.approach) return Vec3(p.min.x(), p.min.y(), p.z + p.approach - s);
  return raster_at_arc(p, r, s - p.approach).first;
}

Vec3 raster_velocity(const RasterPath& p, double t) {
  const RasterLayout r(p);
  if (p.speed <= 0.0) return Vec3::Zero();
  const double s = std::max(t, 0.0) * p.speed;
  if (s < p.approach) return Vec3(0.0, 0.0, -p.speed);
  if (s - p.approach >= r.length) return Vec3::Zero();
  return p.speed * raster_at_arc(p, r, s - p.approach).second;
}

double raster_duration(const RasterPath& p) {
  return p.speed > 0.0 ? (p.approach + RasterLayout(p).length) / p.speed : 0.0;
}

// ---- press ----------------------------------------------------------------------------------

struct PressPhase {
  double travel = 0.0;  ///< distance along direction [m]
  double rate = 0.0;    ///< d(travel)/dt [m/s]
};

PressPhase press_phase(const PressPath& p, double t) {
  if (p.speed <= 0.0 || p.depth <= 0.0 || p.repeat < 1) return {};
  t = std::max(t, 0.0);
  const double stroke = p.depth / p.speed;
  const double hold = std::max(p.hold, 0.0);
  const double cycle = 2.0 * stroke + hold;
  if (t >= cycle * p.repeat) return {};
  const double tau = t - std::floor(t / cycle) * cycle;
  if (tau < stroke) return {p.speed * tau, p.speed};
  if (tau < stroke + hold) return {p.depth, 0.0};
  const double back = tau - stroke - hold;
  return {std::max(p.depth - p.speed * back, 0.0), -p.speed};
}

double press_duration(const PressPath& p) {
  if (p.speed <= 0.0 || p.depth <= 0.0 || p.repeat < 1) return 0.0;
  return (2.0 * p.depth / p.speed + std::max(p.hold, 0.0)) * p.repeat;
}

// ---- circle ---------------------------------------------------------------------------------

/// In-plane basis (u, v, n), right-handed. u is the x axis projected onto the plane (the
/// y axis when the normal is within ~25° of x), so the start point does not depend on
/// anything but the normal.
struct CircleFrame {
  Vec3 u, v;
};

CircleFrame circle_frame(const CirclePath& p) {
  Vec3 n = p.normal;
  if (!(n.norm() > 1e-12)) n = Vec3::UnitZ();
  n.normalize();
  const Vec3 ref = std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  const Vec3 u = (ref - ref.dot(n) * n).normalized();
  return {u, n.cross(u)};
}

double circle_angle(const CirclePath& p, double t) {
  // Reducing t modulo the period first keeps the angle exact for long runs.
  const double phase = std::fmod(std::max(t, 0.0), p.period) / p.period;
  return 2.0 * std::numbers::pi * phase;
}

Vec3 circle_position(const CirclePath& p, double t) {
  const CircleFrame f = circle_frame(p);
  if (!(p.period > 0.0)) return p.center + p.radius * f.u;
  const double a = circle_angle(p, t);
  return p.center + p.radius * (std::cos(a) * f.u + std::sin(a) * f.v);
}

Vec3 circle_velocity(const CirclePath& p, double t) {
  if (!(p.period > 0.0)) return Vec3::Zero();
  const CircleFrame f = circle_frame(p);
  const double a = circle_angle(p, t);
  const double omega = 2.0 * std::numbers::pi / p.period;
  return p.radius * omega * (-std::sin(a) * f.u + std::cos(a) * f.v);
}

// ---- needle line ----------------------------------------------------------------------------

double needle_length(const NeedleLinePath& p) { return (p.target - p.entry).norm(); }

Vec3 needle_position(const NeedleLinePath& p, double t) {
  const double length = needle_length(p);
  if (length <= 0.0 || p.speed <= 0.0) return p.entry;
  const double travelled = std::max(t, 0.0) * p.speed;
  if (travelled >= length) return p.target;  // exactly the target, no rounding
  return p.entry + (travelled / length) * (p.target - p.entry);
}

Vec3 needle_velocity(const NeedleLinePath& p, double t) {
  const double length = needle_length(p);
  if (length <= 0.0 || p.speed <= 0.0 || std::max(t, 0.0) * p.speed >= length) return Vec3::Zero();
  return (p.speed / length) * (p.target - p.entry);
}

double needle_duration(const NeedleLinePath& p) {
  return p.speed > 0.0 ? needle_length(p) / p.speed : 0.0;
}

// ---- tremor ---------------------------------------------------------------------------------

/// A small integer mixer (lowbias32): well spread bits from consecutive inputs.
std::uint32_t mix(std::uint32_t x) {
  x ^= x >> 16;
  x *= 0x7feb352dU;
  x ^= x >> 15;
  x *= 0x846ca68bU;
  x ^= x >> 16;
  return x;
}

double unit_from(std::uint32_t h) { return static_cast<double>(h) / 4294967296.0; }  // [0, 1)

// Three partials per axis around the tremor frequency. Their weights sum to 1/√3 per axis,
// so |component| ≤ amplitude/√3 and the vector norm never exceeds the amplitude.
constexpr std::array<double, 3> kPartialRatio = {0.8, 1.0, 1.25};
constexpr std::array<double, 3> kPartialWeight = {0.5, 0.3, 0.2};

}  // namespace

Vec3 position_at(const Trajectory& trajectory, double t) {
  return std::visit(
      [t](const auto& p) -> Vec3 {
        using P = std::decay_t<decltype(p)>;
        if constexpr (std::is_same_v<P, WaypointsPath>) return waypoints_position(p, t);
        else if constexpr (std::is_same_v<P, RasterPath>) return raster_position(p, t);
        else if constexpr (std::is_same_v<P, PressPath>) return p.position + press_phase(p, t).travel * p.direction;
        else if constexpr (std::is_same_v<P, CirclePath>) return circle_position(p, t);
        else return needle_position(p, t);
      },
      trajectory);
}

Quat orientation_at(const Trajectory& trajectory, double t) {
  const auto* p = std::get_if<WaypointsPath>(&trajectory);
  if (!p) return Quat::Identity();
  return Quat::FromTwoVectors(Vec3(0, 0, -1), waypoints_direction(*p, t));
}

Vec3 velocity_at(const Trajectory& trajectory, double t) {
  return std::visit(
      [t](const auto& p) -> Vec3 {
        using P = std::decay_t<decltype(p)>;
        if constexpr (std::is_same_v<P, WaypointsPath>) return waypoints_velocity(p, t);
        else if constexpr (std::is_same_v<P, RasterPath>) return raster_velocity(p, t);
        else if constexpr (std::is_same_v<P, PressPath>) return press_phase(p, t).rate * p.direction;
        else if constexpr (std::is_same_v<P, CirclePath>) return circle_velocity(p, t);
        else return needle_velocity(p, t);
      },
      trajectory);
}

double duration(const Trajectory& trajectory) {
  return std::visit(
      [](const auto& p) -> double {
        using P = std::decay_t<decltype(p)>;
        if constexpr (std::is_same_v<P, WaypointsPath>) return waypoints_duration(p);
        else if constexpr (std::is_same_v<P, RasterPath>) return raster_duration(p);
        else if constexpr (std::is_same_v<P, PressPath>) return press_duration(p);
        else if constexpr (std::is_same_v<P, CirclePath>) return kInf;
        else return needle_duration(p);
      },
      trajectory);
}

Vec3 tremor_at(const Tremor& tremor, double t, unsigned seed) {
  if (!(tremor.amplitude > 0.0)) return Vec3::Zero();
  const double per_axis = tremor.amplitude / std::sqrt(3.0);
  Vec3 out = Vec3::Zero();
  for (std::uint32_t axis = 0; axis < 3; ++axis) {
    double sum = 0.0;
    for (std::uint32_t k = 0; k < 3; ++k) {
      const std::uint32_t h = mix(mix(seed) ^ (axis * 3U + k + 1U) * 0x9e3779b9U);
      const double phase = 2.0 * std::numbers::pi * unit_from(h);
      // Detune each axis a little (±4 %) so the axes do not move in lockstep.
      const double detune = 1.0 + 0.08 * (unit_from(mix(h)) - 0.5);
      const double f = tremor.frequency * kPartialRatio[k] * detune;
      sum += kPartialWeight[k] * std::sin(2.0 * std::numbers::pi * f * t + phase);
    }
    out[axis] = per_axis * sum;
  }
  return out;
}

}  // namespace tactus::haptics
