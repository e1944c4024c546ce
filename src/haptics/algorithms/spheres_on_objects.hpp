#pragma once
// A finger of contact-law spheres (Hertz, the fingerpad law or a penalty) among many rigid
// objects (seed 000 §3–4: the Hertz finger touching any object of the room): each sphere is
// pressed into the union of the objects' chosen impostor levels (objects.hpp: how the levels
// are chosen and switched), with the law of the object it touches, that object's material,
// and the mean curvature of the level at the contact (the curvature voting each level holds,
// over its own q-rings). Deformable bodies come through the interaction loop's contact plane,
// with the algorithm's own law and the plane's curvature. Across a level switch of the touched
// object the force blends from the old level's to the new one's.
#include <memory>
#include <vector>

#include "haptics/algorithms/contact_law.hpp"
#include "haptics/algorithms/objects.hpp"
#include "haptics/force_algorithm.hpp"

namespace tactus::haptics {

class SpheresOnObjects final : public ForceAlgorithm {
 public:
  /// `laws`: one per object (its material), then one for the contact plane's bodies. Throws
  /// InputError for an object without levels, switch thresholds out of order or a law missing.
  SpheresOnObjects(std::vector<ToolSphere> spheres, std::vector<ContactLaw> laws, double damping,
                   std::vector<TouchableObject> objects, const ObjectsSettings& settings);

  [[nodiscard]] std::unique_ptr<AlgorithmState> make_state() const override;
  [[nodiscard]] Rendering render(const FrameInputs& frame, AlgorithmState& state) const override;
  void react(const FrameInputs& frame, const Rendering& rendered, const Reaction& reaction, AlgorithmState& state,
             ContactLoad& load) const override;

  [[nodiscard]] static std::span<const std::size_t> levels_in_use(const AlgorithmState& state);

 private:
  struct State;
  /// The spheres' summed force and torque against the query as it points now.
  struct Pressed {
    Vec3 force = Vec3::Zero(), torque = Vec3::Zero(), point = Vec3::Zero();
    bool touching = false;
    int member = -1;  ///< what the largest push touched
    double contact_radius = 0.0;
  };
  [[nodiscard]] Pressed press(const FrameInputs& f, const LevelChooser::State& levels) const;

  std::vector<ToolSphere> spheres_;
  std::vector<ContactLaw> laws_;
  double damping_;
  LevelChooser chooser_;
};

}  // namespace tactus::haptics
