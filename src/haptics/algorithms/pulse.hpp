#pragma once
// The arterial pulse felt by palpation (seed 003 §3.5): a rectangular wave (rate in beats per
// minute, duty cycle D = pulse duration / period) from point sources along a vessel, felt
// depending on the tool's distance from the sources and on its orientation to them, and only
// while the tool presses on the tissue (a pulse is felt by pressing).
//
// The law (docs/runtime.md#the-pulse): with n the unit direction in which the tissue pushes
// the hand this frame (the contact force's direction), d_i the distance of the tool centre
// from source i and u_i the unit vector from source i to the tool centre,
//
//   F = A · w(t) · max_i [ fade(d_i) · max(0, n·u_i) ] · n,
//   w(t) = 1 while frac(t · rate / 60) < D, else 0,
//   fade(d) = (1 − d/range)² for d < range, else 0.
//
// Along n, because the vessel's swelling reaches the finger through the tissue it presses:
// the pulse modulates the push the finger already feels, whatever the contact algorithm, and
// never drags the finger sideways (a tangential pulse would fight the proxy's friction). The
// factor n·u_i is the orientation: pressing straight towards the vessel feels it fully,
// touching it from the side less, from behind not at all. fade is C¹ at `range`, so
// crossing the edge of the range is no force step; the largest source term (not their
// sum) keeps the amplitude independent of how many sources there are.
//
// Pure and allocation-free per frame: the sources are fixed at construction.
#include <span>
#include <vector>

#include "core/math.hpp"

namespace tactus::haptics {

struct PulseConfig {
  double rate = 72.0;        ///< [beats/min], > 0
  double duty_cycle = 0.2;   ///< (0, 1)
  double amplitude = 0.3;    ///< A [N], > 0
  double range = 0.03;       ///< distance at which a source's pulse has faded to zero [m], > 0
  std::vector<Vec3> sources; ///< point sources [m], at least one
};

class PulseForce {
 public:
  /// Throws std::invalid_argument for a parameter out of range, no source, or a non-finite one
  /// (the scene loader reports the keys with their location first).
  explicit PulseForce(PulseConfig config);

  /// The rectangular wave at time t [s]: true during the first D of every period.
  [[nodiscard]] bool beating(double t) const;
  /// fade(d) · orientation of the strongest source, in [0, 1], for the tool centre `tool` and
  /// the unit push direction `push` (tissue on hand).
  [[nodiscard]] double weight(const Vec3& tool, const Vec3& push) const;
  /// The pulse force on the hand at time t [N]: zero when `contact_force` (the force the
  /// contact algorithm renders this frame) is zero or not finite, i.e. when not pressing.
  [[nodiscard]] Vec3 force(double t, const Vec3& tool, const Vec3& contact_force) const;

  [[nodiscard]] const PulseConfig& config() const { return config_; }
  [[nodiscard]] double period() const { return 60.0 / config_.rate; }  ///< [s]

 private:
  PulseConfig config_;
};

/// `count` point sources along a body's principal axis: the line through the centroid of
/// `nodes` along the eigenvector of their covariance with the largest eigenvalue, spread over
/// the nodes' extent along it at the centres of `count` equal intervals. For a vessel tube
/// that is its centreline. Throws std::invalid_argument for no node or count < 1.
[[nodiscard]] std::vector<Vec3> pulse_sources_along_axis(std::span<const Vec3> nodes, int count);

}  // namespace tactus::haptics
