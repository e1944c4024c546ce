#pragma once
// A body whose force comes from a field looked up at the tool, not from a contact: a
// precomputed configuration space of nonlinear FEM interpolated at the haptic rate (seed 001;
// compile/cspace_body.hpp implements ForceField). The field takes no load: the body it stands
// for was solved with the tool in place.
#include <memory>
#include <optional>

#include "haptics/force_algorithm.hpp"

namespace tactus::haptics {

struct FieldForce {
  Vec3 force = Vec3::Zero();  ///< the body's force on the tool [N]
  bool touching = false;      ///< the field has a value at the point
  Vec3 torque = Vec3::Zero();  ///< the body's torque on the tool about the point looked up [N·m]
};

class ForceField {
 public:
  virtual ~ForceField() = default;
  /// The force at point p [m], the tool turned by `orientation` (scene frame), at loop time
  /// t [s]. Allocation-free; called by one haptic thread.
  [[nodiscard]] virtual FieldForce force(const Vec3& p, const Quat& orientation, double t) const noexcept = 0;
  /// A field of two points (a two-point configuration space): the force on point `finger` (0
  /// or 1) at p, the other point at `other` (null: not known). A field of one point has no
  /// other and gives force().
  [[nodiscard]] virtual FieldForce force_on(int /*finger*/, const Vec3& p, const Quat& orientation,
                                            const Vec3* /*other*/, double t) const noexcept {
    return force(p, orientation, t);
  }
};

/// A tool at one of a two-point field's points: which, and where the partner tool (the
/// other point's, on the partner device: FrameInputs::peer) looks the field up.
struct FieldPoint {
  int finger = 0;
  Vec3 partner_offset = Vec3::Zero();  ///< in the partner tool's frame [m]
};

class FieldLookup final : public ForceAlgorithm {
 public:
  /// `offset`: the point of the tool the field is looked up at, in the tool frame [m].
  /// `point`: the tool's point of a two-point field; none: the field has one point.
  FieldLookup(std::shared_ptr<const ForceField> field, Vec3 offset, std::optional<FieldPoint> point = std::nullopt)
      : field_(std::move(field)), offset_(offset), point_(point) {}

  [[nodiscard]] std::unique_ptr<AlgorithmState> make_state() const override {
    return std::make_unique<AlgorithmState>();
  }
  [[nodiscard]] Rendering render(const FrameInputs& frame, AlgorithmState& state) const override;
  void react(const FrameInputs& frame, const Rendering& rendered, const Reaction& reaction, AlgorithmState& state,
             ContactLoad& load) const override;
  [[nodiscard]] bool simulation_follows_tool() const override { return true; }

 private:
  std::shared_ptr<const ForceField> field_;
  Vec3 offset_;
  std::optional<FieldPoint> point_;
};

}  // namespace tactus::haptics
