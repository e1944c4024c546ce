#pragma once
// Device trajectories: plain parameter structs (filled in by the scene loader) and their
// evaluation at a time t. Positions are in device coordinates [m], times in seconds from
// the start of the run. Evaluation is pure: the same t gives the same point, bit for bit.
#include <variant>
#include <vector>

#include "core/math.hpp"

namespace tactus::haptics {

struct Waypoint {
  double time = 0.0;  ///< [s]
  Vec3 position = Vec3::Zero();
  /// Where the handle's −z axis points (a needle's shaft towards its tip); unit.
  Vec3 direction = Vec3(0, 0, -1);
};
struct WaypointsPath {
  std::vector<Waypoint> points;  ///< times strictly increasing
  bool loop = false;
};
/// Boustrophedon scan of the rectangle [min, max] in x–y at height z (palpation), after an
/// optional approach from above.
struct RasterPath {
  Vec2 min = Vec2::Zero();
  Vec2 max = Vec2::Zero();
  double z = 0.0;
  double spacing = 0.005;  ///< between scan lines [m]
  double speed = 0.02;     ///< [m/s]
  /// [m]: the scan starts this far above z over its first corner and comes straight down at
  /// `speed` (a hand put down on the tissue rather than one that starts inside it).
  double approach = 0.0;
};
/// Move from `position` along `direction` by `depth`, hold, return; `repeat` times.
struct PressPath {
  Vec3 position = Vec3::Zero();
  Vec3 direction = Vec3(0, 0, -1);  ///< unit
  double depth = 0.005;
  double speed = 0.01;
  double hold = 1.0;  ///< [s]
  int repeat = 1;
};
struct CirclePath {
  Vec3 center = Vec3::Zero();
  Vec3 normal = Vec3(0, 0, 1);  ///< unit
  double radius = 0.01;
  double period = 2.0;  ///< [s]
};
/// Straight insertion from entry towards target at constant speed.
struct NeedleLinePath {
  Vec3 entry = Vec3::Zero();
  Vec3 target = Vec3::Zero();
  double speed = 0.005;
};
using Trajectory = std::variant<WaypointsPath, RasterPath, PressPath, CirclePath, NeedleLinePath>;

struct Tremor {
  double amplitude = 0.0;   ///< [m]; 0 = none
  double frequency = 8.0;   ///< [Hz]
};

/// The target position at time t ≥ 0 (before tremor). Paths that end (waypoints without
/// loop, raster, press, needle line) hold their last point afterwards.
[[nodiscard]] Vec3 position_at(const Trajectory& trajectory, double t);
/// The handle's orientation at t: waypoints turn the −z axis from one waypoint's direction to
/// the next's (normalized linear blend); every other path keeps the identity.
[[nodiscard]] Quat orientation_at(const Trajectory& trajectory, double t);
/// Velocity of the target at t (analytic where the path is smooth; one-sided at corners).
[[nodiscard]] Vec3 velocity_at(const Trajectory& trajectory, double t);
/// Time at which the path ends; +infinity for paths that never end (circle, looped waypoints).
[[nodiscard]] double duration(const Trajectory& trajectory);

/// Hand tremor: a deterministic, band-limited wobble of the given amplitude around the
/// tremor frequency (a sum of a few sinusoids with fixed phases from `seed`). Zero when
/// amplitude is 0.
[[nodiscard]] Vec3 tremor_at(const Tremor& tremor, double t, unsigned seed = 0);

}  // namespace tactus::haptics
