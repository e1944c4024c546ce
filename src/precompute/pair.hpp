#pragma once
// Two-point spaces (docs/precompute.md, "Two-point spaces"): configuration spaces of two
// interaction points (two fingers, or two instruments) pressing the same body. Seed 001
// (§3.4) names multi-point interaction beside the probe: "each degree of freedom yields
// additional dimension of the grid". The six-dimensional grid is built as levels, each a
// whole point space built by the same scheduler:
//
//   level 0              the first point's space, the second free (not touching);
//   level 1              the second point's space, the first free;
//   levels 2 .. 2+nB−1   the first point's space with the second held at its grid point j;
//   the nA levels after  the second point's space with the first held at its grid point i.
//
// Each point's force is interpolated within its own levels by the space's method (its own
// position, where the force changes fastest) and across them in the other point's position
// by triquadratic Lagrange over the 3 × 3 × 3 levels around it (exact where the force is
// quadratic in the other's position), or trilinearly over the 8 around it where one of the
// 27 has no value at the point. A configuration with both points at grid points is solved
// twice (once in each point's levels), since each point's force needs its own position's
// derivatives.
// precompute_bench twopoint measures the route against direct two-point solves and against
// superposing two point spaces (docs/validation.md).
#include <array>
#include <cstddef>
#include <memory>
#include <optional>
#include <vector>

#include "core/math.hpp"
#include "precompute/grid.hpp"
#include "precompute/interpolator.hpp"
#include "precompute/settings.hpp"
#include "precompute/space.hpp"

namespace tactus::precompute {

/// `settings` seen from point `finger` (0: the scene's first, 1: its second): the contact
/// node, patch and box are that point's, `pair` the other's. The other point is free.
[[nodiscard]] SpaceSettings pair_point(const SpaceSettings& settings, int finger);
/// The grid of a point's levels: through its contact node's rest place in `rest` (3N).
[[nodiscard]] Grid pair_grid(const SpaceSettings& settings, int finger, const VecX& rest);

/// Every level a space is built as, in level order: a point space's one, a probe space's
/// leans (precompute/probe.hpp), or a two-point space's 2 + nA + nB (above). `rest`: the
/// body's rest positions (3N), which place a two-point space's grids.
[[nodiscard]] std::vector<SpaceSettings> space_levels(const SpaceSettings& settings, const VecX& rest);

class PairInterpolator {
 public:
  /// `levels`: a two-point space's levels in level order. Throws InputError when their number,
  /// points, grids or held places disagree.
  PairInterpolator(std::vector<std::shared_ptr<const Space>> levels, Interpolation method);

  /// The force on point `finger` (0 or 1) at p [m], the other point at `other`; null, or
  /// outside the other point's grid box: the other is free (it does not touch). Allocation-
  /// free. Valid where at least one level around the other has a value at p. Where one of
  /// the 27 levels around the other point has none, the stencil made linear along one axis,
  /// then two, where that leaves it out (levels_lowered); else trilinear across levels, its
  /// weight going to the others (across_levels). fallback: a level used fell back within
  /// itself.
  [[nodiscard]] Query force(int finger, const Vec3& p, const Vec3* other) const noexcept;
  /// The same with the nodal displacements (3N), trilinear across levels (the 8 around the
  /// other point; the force is that of the same levels). One thread at a time (a scratch
  /// vector).
  Query shape(int finger, const Vec3& p, const Vec3* other, VecX& displacement) const;

  /// Point `finger`'s grid (that of its levels).
  [[nodiscard]] const Grid& grid(int finger) const { return alone(finger).space().grid; }
  /// Whether p lies in point `finger`'s grid box.
  [[nodiscard]] bool in_box(int finger, const Vec3& p) const;
  [[nodiscard]] std::size_t level_count() const { return levels_.size(); }
  [[nodiscard]] const Interpolator& level(std::size_t k) const { return levels_[k]; }

 private:
  struct Stencil {
    std::array<std::size_t, 27> level{};
    std::array<double, 27> weight{};
    /// Each level's place in the 3 × 3 × 3 block of levels around the other point's nearest
    /// interior grid point (i + 3j + 9k): every stencil draws on that block.
    std::array<int, 27> slot{};
    int count = 0;
  };
  [[nodiscard]] const Interpolator& alone(int finger) const { return levels_[static_cast<std::size_t>(finger)]; }
  /// The levels of `finger` around the other point's place, per axis quadratic (the 3 levels
  /// around the nearest interior one) or linear (the 2 of its cell), or its free level.
  [[nodiscard]] Stencil stencil(int finger, const Vec3* other, std::array<bool, 3> quadratic) const noexcept;
  static constexpr std::array<bool, 3> kQuadratic{true, true, true}, kLinear{false, false, false};
  /// Σ weight · (a level's query), through `query(stencil, entry)`; with `renormalize`, the
  /// levels without a value are left out and the others' weights scaled to sum to one.
  struct Combined {
    Query query;
    double kept = 0.0;  ///< the weight of the levels that had a value
  };
  template <class LevelQuery>
  Combined combine(const Stencil& s, bool renormalize, LevelQuery query) const;

  std::vector<Interpolator> levels_;
  mutable VecX scratch_;
};

}  // namespace tactus::precompute
