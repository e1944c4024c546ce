#pragma once
// One solver of configurations: static equilibria of a body with its contact patch held at a
// grid point. A configuration is reached by a transition from an already solved neighbour:
// the patch moves along the grid edge in load steps, each a Newton solve warm-started from
// the last. The solver keeps one BodyState for its whole life, so the sparse Cholesky
// factorization's symbolic analysis (done on the first solve) is reused by every later one.
// In a probe space the patch also turns with the probe, about the contact node, by the
// level's lean; the start point of a leaning level is reached by turning it in load steps.
#include <cstdint>

#include "physics/body.hpp"
#include "precompute/settings.hpp"
#include "precompute/space.hpp"

namespace tactus::precompute {

/// A load step that stops short of the relative tolerance still counts as converged when
/// the out-of-balance force on the free nodes is below this [N] (physics::StaticSettings's
/// floor): a patch barely pressed has reactions so small that the relative criterion sits
/// at round-off.
inline constexpr double kAbsoluteForceTolerance = 1e-9;

class ConfigurationSolver {
 public:
  /// `body`: the scene body (its fixed dofs are the fixed regions). The solver adds the
  /// patch nodes as prescribed dofs, solves with sparse Cholesky, and drops gravity unless
  /// settings.gravity. Throws InputError for a patch node out of range or already fixed.
  ConfigurationSolver(const physics::Body& body, const SpaceSettings& settings);

  /// The start configuration: the patch at `target` (its rest position: the undeformed
  /// contact point), reached from the rest shape.
  PointResult solve_start(std::size_t point, const Vec3& target);
  /// The configuration at `target`, reached from the solved configuration `source` (its
  /// displacement and its patch position `from`) in settings.load_steps load steps.
  PointResult transition(std::size_t point, std::int64_t source, const VecX& source_displacement, const Vec3& from,
                         const Vec3& target);
  /// A path from rest straight to `target` in `steps` load steps (the reference solution of
  /// the accuracy study, independent of the grid), the probe turning from rest to its level's
  /// lean on the way.
  PointResult solve_direct(const Vec3& target, int steps);
  /// The same with the probe turned by `rotation` (a rotation vector) at the end: the
  /// reference of a probe space between its leans.
  PointResult solve_direct(const Vec3& target, const Vec3& rotation, int steps);

  /// Rest position of the contact node.
  [[nodiscard]] const Vec3& contact_rest() const { return contact_rest_; }
  [[nodiscard]] const physics::Body& body() const { return body_; }
  /// Total Newton iterations and factorizations so far.
  [[nodiscard]] long long newton_iterations() const { return newton_iterations_; }

 private:
  /// Where the patch is held: the contact node's place and the probe's rotation vector; and
  /// how far the held second node (settings.held_node) has come from rest to held_at.
  struct Pose {
    Vec3 contact = Vec3::Zero();
    Vec3 rotation = Vec3::Zero();
    double held = 1.0;
  };
  PointResult run(std::size_t point, std::int64_t source, const VecX* start, const Pose& from, const Pose& target,
                  int steps);
  void place_patch(const Pose& pose);
  /// The patch's reactions at the balanced state: their sum into r.force, their moment about
  /// the contact node into r.torque.
  void reaction(PointResult& r);
  /// Fills r's force and displacement gradients at the balanced state; false where the
  /// stiffness does not solve.
  bool derivatives(PointResult& r);

  physics::Body body_;
  SpaceSettings settings_;
  physics::BodyState state_;
  Vec3 contact_rest_ = Vec3::Zero();
  Vec3 rotation_ = Vec3::Zero();  ///< the probe's at this level's lean (precompute/probe.hpp)
  VecX force_;
  MatX held_, force_change_;
  long long newton_iterations_ = 0;
};

}  // namespace tactus::precompute
