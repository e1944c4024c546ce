#pragma once
// A body whose force comes from a field looked up at the tool, not from a contact: a
// precomputed configuration space of nonlinear FEM interpolated at the haptic rate (seed 001;
// compile/cspace_body.hpp implements ForceField). The field takes no load: the body it stands
// for was solved with the tool in place.
#include <memory>

#include "haptics/force_algorithm.hpp"

namespace tactus::haptics {

struct FieldForce {
  Vec3 force = Vec3::Zero();  ///< the body's force on the tool [N]
  bool touching = false;      ///< the field has a value at the point
};

class ForceField {
 public:
  virtual ~ForceField() = default;
  /// The force at point p [m], the tool turned by `orientation` (scene frame), at loop time
  /// t [s]. Allocation-free; called by one haptic thread.
  [[nodiscard]] virtual FieldForce force(const Vec3& p, const Quat& orientation, double t) const noexcept = 0;
};

class FieldLookup final : public ForceAlgorithm {
 public:
  /// `offset`: the point of the tool the field is looked up at, in the tool frame [m].
  FieldLookup(std::shared_ptr<const ForceField> field, Vec3 offset) : field_(std::move(field)), offset_(offset) {}

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
};

}  // namespace tactus::haptics
