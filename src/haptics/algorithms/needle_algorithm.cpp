#include "haptics/algorithms/needle_algorithm.hpp"

namespace tactus::haptics {

NeedleAlgorithm::NeedleAlgorithm(NeedleConfig config, std::optional<Vec3> fixed_axis)
    : config_(std::move(config)), fixed_axis_(fixed_axis) {
  const NeedleInsertion check(config_);  // the configuration's errors at build time
}

std::unique_ptr<AlgorithmState> NeedleAlgorithm::make_state() const { return std::make_unique<State>(config_); }

const NeedleInsertion& NeedleAlgorithm::insertion(const AlgorithmState& state) {
  return static_cast<const State&>(state).needle;
}

Rendering NeedleAlgorithm::render(const FrameInputs& f, AlgorithmState& state) const {
  auto& s = static_cast<State&>(state);
  // A handle's needle points along its −z; a scripted line fixes the axis to the line.
  const Vec3 axis = fixed_axis_ ? *fixed_axis_ : Vec3(f.orientation * Vec3(0, 0, -1));
  const double norm = axis.norm();
  if (norm > 1e-9 && axis.allFinite()) {
    s.axis = axis / norm;
  } else if (s.axis.isZero()) {
    s.axis = Vec3(0, 0, -1);
  }
  s.out = s.needle.update(f.position, s.axis, f.velocity, *f.surfaces, f.t);
  Rendering r;
  if (s.out.rupture) {
    r.has_event = true;
    r.event = {HapticEvent::Kind::rupture, s.out.rupture->force, static_cast<std::int32_t>(s.out.rupture->layer)};
  }
  r.force = s.out.force;
  r.touching = s.out.touching;
  r.point = s.out.load_point;
  r.law_force = s.out.spring_force;
  r.tool_axis = s.axis;
  r.surface_time = f.contact->surface_time;
  r.frame_point = plane_frame_point(*f.contact);
  return r;
}

void NeedleAlgorithm::react(const FrameInputs& f, const Rendering& rendered, const Reaction& reaction,
                            AlgorithmState& state, ContactLoad& load) const {
  const auto& s = static_cast<const State&>(state);
  const int layer = s.out.load_layer;
  load.active = rendered.touching && layer >= 0 && s.out.load_triangle >= 0;
  load.body = layer >= 0 ? static_cast<std::int32_t>(config_.layers[static_cast<std::size_t>(layer)].body) : -1;
  load.triangle = load.active ? s.out.load_triangle : -1;
  load.barycentric = s.out.load_barycentric;
  if (rendered.touching && s.out.shaft && load.body >= 0) {
    // The lateral spring's reaction goes along the shaft; the point load keeps the rest.
    const Vec3 lateral = reaction.kept * s.out.lateral_force;
    load.shaft = true;
    load.shaft_from = s.out.shaft_from;
    load.shaft_to = f.position;
    load.shaft_force = -lateral;
    load.force += lateral;
  }
}

}  // namespace tactus::haptics
