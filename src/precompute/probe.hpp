#pragma once
// Probe spaces (docs/precompute.md, "Probe spaces"): configuration spaces of a rigid probe
// whose end is bonded to the contact patch and which may lean away from its rest axis. Seed
// 001 (§3.4) names this as the next step: "the probe interaction introduces additional levels
// for each grid point". Here a level is a whole point space at one lean, built by the same
// scheduler; the levels form a square lattice of leans.
//
// A lean is a point t = (t1, t2) of the rest axis's tangent plane (the azimuthal equidistant
// map): the probe's direction is the rest axis turned by |t| radians towards t1·e1 + t2·e2.
// The map has no singularity within a half-turn of the axis, and no roll: a direction
// determines the probe's rotation (the shortest turn from the rest axis), which is what a
// probe symmetric about its axis needs.
//
// Between leans, the force and the shape are the biquadratic Lagrange interpolation over the
// 3 × 3 levels around the lean (exact where they vary quadratically with the lean, which a
// probe leaning either way from a symmetric rest does to first order), each level
// interpolated in position by the space's own method.
#include <array>
#include <cstddef>
#include <memory>
#include <vector>

#include "core/math.hpp"
#include "precompute/interpolator.hpp"
#include "precompute/settings.hpp"
#include "precompute/space.hpp"

namespace tactus::precompute {

/// The rest axis and its tangent frame: e1 and e2 unit, orthogonal to the axis and to each
/// other, e1 × e2 = axis. e1 is the coordinate axis least aligned with the probe, projected.
struct ProbeFrame {
  explicit ProbeFrame(const Vec3& axis);
  /// The rotation vector (axis × angle) that turns the rest axis to lean t.
  [[nodiscard]] Vec3 rotation(const Vec2& tilt) const;
  /// The probe's direction at lean t (unit).
  [[nodiscard]] Vec3 direction(const Vec2& tilt) const;
  /// The lean of a direction (of any length > 0): its angle from the axis along its tangent
  /// part. The axis itself, and a zero or non-finite direction, give zero.
  [[nodiscard]] Vec2 tilt(const Vec3& direction) const;

  Vec3 axis = Vec3::UnitZ(), e1 = Vec3::UnitX(), e2 = Vec3::UnitY();
};

/// Level k's lean: (a, b) = (k mod n, k div n) on the lattice of n = tilt_levels leans per
/// tangent axis from −max_tilt to max_tilt. Zero without a probe.
[[nodiscard]] Vec2 level_tilt(const ProbeSettings& probe, std::size_t level);
/// The settings of level k: `settings` with that level's lean.
[[nodiscard]] SpaceSettings level_settings(const SpaceSettings& settings, std::size_t level);
/// The rotation vector of the probe at its level's lean (zero without a probe).
[[nodiscard]] Vec3 probe_rotation(const SpaceSettings& settings);

class ProbeInterpolator {
 public:
  /// `levels`: a probe space's level_count() levels in level order. Throws InputError when
  /// their number, leans, grids or probes disagree.
  ProbeInterpolator(std::vector<std::shared_ptr<const Space>> levels, Interpolation method);

  /// The force at interaction point p [m] with the probe pointing along `direction` (a lean
  /// beyond max_tilt is clamped onto it). Allocation-free. Valid where every level used has a
  /// value at p; outside and fallback where any level's query was.
  [[nodiscard]] Query force(const Vec3& p, const Vec3& direction) const noexcept;
  /// The force and the torque about the probe's end (Interpolator::force_and_torque), between
  /// the leans as force() is. Allocation-free.
  [[nodiscard]] Query force_and_torque(const Vec3& p, const Vec3& direction) const noexcept;
  /// The force and the nodal displacements (3N). Allocates only when `displacement` has
  /// another size; one thread at a time (it keeps a scratch vector).
  Query shape(const Vec3& p, const Vec3& direction, VecX& displacement) const;

  [[nodiscard]] std::size_t level_count() const { return levels_.size(); }
  [[nodiscard]] const Interpolator& level(std::size_t k) const { return levels_[k]; }
  [[nodiscard]] const ProbeFrame& frame() const { return frame_; }

 private:
  struct Stencil {
    std::array<std::size_t, 9> level{};
    std::array<double, 9> weight{};
  };
  [[nodiscard]] Stencil stencil(const Vec3& direction) const noexcept;
  /// force(), and with Torque force_and_torque().
  template <bool Torque>
  [[nodiscard]] Query between_leans(const Vec3& p, const Vec3& direction) const noexcept;

  ProbeSettings probe_;
  ProbeFrame frame_;
  std::vector<Interpolator> levels_;
  mutable VecX scratch_;
};

}  // namespace tactus::precompute
