#pragma once
// A body rendered from a precomputed configuration space (scene kind = "cspace"): the haptic
// loop reads the force at the tool's interaction point from the space's Interpolator, and
// the simulation loop publishes the interpolated shape instead of simulating the body.
// A probe space (levels of leans, precompute/probe.hpp) is looked up with the tool's −z axis
// as the probe's direction. A two-point space (precompute/pair.hpp) is felt by two tools on
// two devices, the body's `tools`: each tool's force comes from its point's levels at its
// own position and its partner's.
// With `online = true` the space is built during the run (precompute::OnlineBuilder): solver
// threads work around the tool and ahead of it, and the force comes from the points solved
// so far.
#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "core/math.hpp"
#include "haptics/algorithms/field_lookup.hpp"
#include "precompute/interpolator.hpp"
#include "precompute/online.hpp"
#include "precompute/pair.hpp"
#include "precompute/probe.hpp"
#include "scene/model.hpp"

namespace tactus::compile {

/// The force the body exerts on the tool [N], and whether the point lies in the space's
/// grid box and has a value.
using CspaceForce = haptics::FieldForce;

class CspaceBody final : public haptics::ForceField {
 public:
  /// Loads the space of scene body `index` (its kind = "cspace") and checks that it was built
  /// for this body: throws InputError, located at the space file, for another mesh, material,
  /// fixed region or a missing or malformed file.
  /// An on-line body (online = true) starts its solver threads here, from the scene's
  /// [precompute] table (InputError, located, when there is none for this body). Load each
  /// body once per run and share it: the haptic and simulation loops hold the same object.
  static std::shared_ptr<const CspaceBody> load(const scene::Model& model, std::size_t index);

  /// The force at interaction point p [m], the tool turned by `orientation`, at loop time t
  /// [s]. Outside the grid's box the tool is not attached and feels nothing. Allocation-free.
  /// On-line: the tool's position feeds the solvers' prediction, and only the haptic thread
  /// may call it.
  [[nodiscard]] CspaceForce force(const Vec3& p, const Quat& orientation, double t) const noexcept override;
  /// A two-point space: the force on point `finger` at p, the other point at `other` (null:
  /// not known; outside its box: free). A space of one point: force().
  [[nodiscard]] CspaceForce force_on(int finger, const Vec3& p, const Quat& orientation, const Vec3* other,
                                     double t) const noexcept override;
  /// Node positions (3N) of the configuration at p: rest + interpolated displacement; the
  /// rest shape where the space has no value. Allocates only when x has another size. One
  /// thread at a time (the simulation loop's).
  void positions(const Vec3& p, const Quat& orientation, VecX& x) const;
  /// A two-point space's shape with its points at `first` and `second` (null: not known):
  /// the first point's levels while it lies in its box, else the second's; the rest shape
  /// when neither does. A space of one point: its shape at `first` (x unchanged when null).
  void positions(const Vec3* first, const Vec3* second, VecX& x) const;

  [[nodiscard]] std::size_t body() const { return body_; }
  [[nodiscard]] bool online() const { return online_ != nullptr; }
  /// Points solved so far (on-line), or the space's solved points.
  [[nodiscard]] std::size_t solved_points() const;
  struct OnlineCounts {
    std::size_t solved = 0, points = 0;  ///< grid points solved, of all
    std::uint64_t queries = 0;           ///< force() calls inside the grid's box
    std::uint64_t complete = 0;          ///< of those, with every corner of their cell resolved
  };
  [[nodiscard]] OnlineCounts online_counts() const;
  /// Where the tool was in force() calls: inside the grid's box or out of it (no force
  /// there), and the time of the first call inside [s] (negative: never).
  struct BoxCounts {
    std::uint64_t inside = 0, outside = 0;
    double first_inside = -1.0;
  };
  [[nodiscard]] BoxCounts box_counts() const;
  /// The file's interpolator (a point space's, not on-line).
  [[nodiscard]] const precompute::Interpolator& interpolator() const { return *interpolator_; }
  /// A probe space's interpolator, or null.
  [[nodiscard]] const precompute::ProbeInterpolator* probe() const { return probe_ ? &*probe_ : nullptr; }
  /// A two-point space's interpolator, or null.
  [[nodiscard]] const precompute::PairInterpolator* pair() const { return pair_ ? &*pair_ : nullptr; }
  /// A two-point space's tools (indices into the scene's tools): at its first and second point.
  [[nodiscard]] const std::array<std::size_t, 2>& pair_tools() const { return pair_tools_; }
  /// The probe's direction for a tool turned by `orientation`: its −z axis.
  [[nodiscard]] static Vec3 probe_direction(const Quat& orientation) { return orientation * Vec3(0.0, 0.0, -1.0); }

  CspaceBody(std::size_t body, std::shared_ptr<const precompute::Space> space, precompute::Interpolation method);
  CspaceBody(std::size_t body, std::vector<std::shared_ptr<const precompute::Space>> levels,
             precompute::Interpolation method);
  CspaceBody(std::size_t body, std::unique_ptr<precompute::OnlineBuilder> online, VecX rest);
  CspaceBody(std::size_t body, precompute::PairInterpolator pair, std::array<std::size_t, 2> tools);
  ~CspaceBody();

 private:
  /// Counts a force() call inside or outside the grid's box.
  void count_box(bool in_box, double t) const noexcept;

  std::size_t body_;
  std::optional<precompute::Interpolator> interpolator_;
  std::optional<precompute::ProbeInterpolator> probe_;
  std::optional<precompute::PairInterpolator> pair_;
  std::array<std::size_t, 2> pair_tools_{};
  /// On-line: written by its solver threads, read by the haptic thread (force) and the
  /// simulation thread (shape); its own synchronization makes that safe.
  std::unique_ptr<precompute::OnlineBuilder> online_;
  VecX rest_;
  // Counted by the haptic thread, read after the run (or while it runs, approximately).
  mutable std::atomic<std::uint64_t> queries_{0}, complete_{0};
  mutable std::atomic<std::uint64_t> inside_{0}, outside_{0};
  mutable std::atomic<double> first_inside_{-1.0};
};

/// Per scene body, its cspace body (null for the others): what one run shares between loops.
using CspaceBodies = std::vector<std::shared_ptr<const CspaceBody>>;
CspaceBodies load_cspace_bodies(const scene::Model& model);
/// The shared one of `bodies` when given, else a fresh load.
std::shared_ptr<const CspaceBody> cspace_body(const scene::Model& model, std::size_t index, const CspaceBodies& bodies);

}  // namespace tactus::compile
