#pragma once
// One interface for every force law of the haptic loop. An algorithm holds its parameters
// and is immutable once built; what changes from frame to frame lives in the state it makes,
// which the haptic step owns (haptics/haptic_step.hpp). The step calls each algorithm twice a
// frame: render() before the smoothing, passivity and safety stages, react() after them with
// the force actually sent, so that the tissue (and a local model) takes what the hand felt.
//
// Two stages: `contact` algorithms render the force of touching the tissue (one per tool);
// `overlay` algorithms add a force while the contact touches (the pulse), after the contact's
// smoothing and passivity control, since their beats are no model update.
#include <cstdint>
#include <memory>

#include "contact/local_model.hpp"
#include "core/math.hpp"
#include "haptics/algorithms/needle.hpp"
#include "haptics/exchange.hpp"

namespace tactus::haptics {

/// What one frame gives every algorithm: the tool and what the other loops last published.
struct FrameInputs {
  double t = 0.0;   ///< loop time [s]
  double dt = 0.0;  ///< since the previous frame [s]
  Vec3 position = Vec3::Zero();        ///< tool frame origin, scene [m]
  Quat orientation = Quat::Identity(); ///< tool frame, scene
  Vec3 velocity = Vec3::Zero();        ///< low-passed tool velocity [m/s]
  const LocalContact* contact = nullptr;  ///< the interaction loop's newest plane (never null)
  bool contact_fresh = false;             ///< it arrived this frame
  const contact::LocalPatch* patch = nullptr;  ///< the simulation's newest patch; null: none requested
  /// The one before it, which the channel still holds this frame (a local model referring to
  /// it may still read it); null: none.
  const contact::LocalPatch* patch_previous = nullptr;
  bool patch_fresh = false;
  const NeedleSurfaces* surfaces = nullptr;  ///< the newest ray crossings (needle, multi-surface)
  bool surfaces_fresh = false;
  /// The partner finger's newest frame (two-finger fabric algorithms); null: no partner.
  const PeerFinger* peer = nullptr;
  /// The step smooths force steps at model updates: report them (Rendering::model_changed).
  bool smoothing = false;
  /// Overlay stage only: the contact force after smoothing and passivity, and whether it touches.
  Vec3 contact_force = Vec3::Zero();
  bool contact_touching = false;
};

/// Something the step reports for the run's record (the loop turns it into a LoopEvent).
struct HapticEvent {
  enum class Kind : std::uint8_t {
    contact_begin, contact_end, force_clamped, non_finite_force, watchdog_trip, device_stall, emergency_stop, rupture,
    contact_state,  ///< value: the two-finger contact state, 1..9 for Table I's I..IX (contact/grasp_state.hpp)
    level_switch,   ///< value: an object's new impostor level (0 coarsest); detail: its body index
    level_cost      ///< value: the largest summed cost of the levels in use over the last 100 ms [s]
  };
  Kind kind = Kind::contact_begin;
  double value = 0.0;
  std::int32_t detail = -1;  ///< rupture: the torn layer's index
};

/// An algorithm's force for one frame, and what the reaction and the frame record need.
struct Rendering {
  Vec3 force = Vec3::Zero();   ///< on the hand, scene [N]
  Vec3 torque = Vec3::Zero();  ///< about the tool origin [N·m]
  bool touching = false;
  Vec3 point = Vec3::Zero();   ///< contact point on the surface [m]
  /// The point the frame records as the proxy (recording.hpp: HapticFrame::proxy).
  Vec3 frame_point = Vec3::Zero();
  double law_force = 0.0;       ///< normal force of the contact law [N]
  double contact_radius = 0.0;  ///< of the contact disc a load may be spread over [m]
  contact::PatchContact on_patch;  ///< patch algorithms: the contact the patch is dented by
  /// When the model rendered was published (loop time) [s]: the watchdog's measure. An
  /// algorithm that renders nothing the simulation publishes (a fixed virtual wall) gives
  /// the frame's time.
  double surface_time = 0.0;
  /// Unit axis the interaction loop casts its ray along next (needle, multi-surface); zero otherwise.
  Vec3 tool_axis = Vec3::Zero();
  /// The local model changed this frame: at this frame the old one gave `before`, the new one `after`.
  bool model_changed = false;
  Vec3 before = Vec3::Zero(), after = Vec3::Zero();
  bool has_event = false;
  HapticEvent event;
  /// Two-finger algorithms: the contact state of seed 002 Table I (1..9), 0 for the others;
  /// and what the partner finger's loop is told (PeerFinger).
  std::uint8_t contact_state = 0;
  bool on_fabric = false;
  bool slipping = false;
  MaterialPoint held;
  /// A grasping finger's pad, which keeps the held body's nodes out (ContactLoad::Pad).
  ContactLoad::Pad pad;
};

/// The force that reached the hand, for the tissue's side of the contact.
struct Reaction {
  Vec3 sent = Vec3::Zero();  ///< the contact's share of the force sent, scene [N]
  double kept = 0.0;         ///< sent / rendered magnitude after the safety layer, in [0, 1]
};

/// A contact whose coupling a user may edit while the run goes on (the viewer's panel).
struct SurfaceValues {
  double stiffness = 0.0;         ///< [N/m]
  double static_friction = 0.0;   ///< μs (proxy only)
  double kinetic_friction = 0.0;  ///< μk ≤ μs (proxy only)
};
struct EditableSurface {
  enum class Kind : std::uint8_t { none, proxy, penalty };
  Kind kind = Kind::none;
  SurfaceValues values;  ///< the scene's
};

/// An algorithm's own mutable state, made by ForceAlgorithm::make_state.
struct AlgorithmState {
  virtual ~AlgorithmState() = default;
};

class ForceAlgorithm {
 public:
  enum class Stage : std::uint8_t { contact, overlay };
  virtual ~ForceAlgorithm() = default;

  [[nodiscard]] virtual Stage stage() const { return Stage::contact; }
  /// Called once before the loop runs: everything the algorithm will need, sized.
  [[nodiscard]] virtual std::unique_ptr<AlgorithmState> make_state() const = 0;
  /// The frame's force. No allocation, no lock, no exception.
  [[nodiscard]] virtual Rendering render(const FrameInputs& frame, AlgorithmState& state) const = 0;
  /// The tissue's side (contact stage only): fills `load` (its force is already −sent) and
  /// advances whatever the algorithm's model does under the force sent. The default is the
  /// contact plane's: the load goes where the plane touches.
  virtual void react(const FrameInputs& frame, const Rendering& rendered, const Reaction& reaction,
                     AlgorithmState& state, ContactLoad& load) const;
  /// Whether the simulation needs the tool's position (to cut a patch around it, or to show
  /// a precomputed configuration).
  [[nodiscard]] virtual bool simulation_follows_tool() const { return false; }
  [[nodiscard]] virtual EditableSurface editable_surface() const { return {}; }
  /// A live edit, validated and bounded by the step.
  virtual void edit_surface(const SurfaceValues& /*values*/, AlgorithmState& /*state*/) const {}
};

/// The contact plane's load: where `contact` touches, while `touching`.
void plane_load(const LocalContact& contact, bool touching, ContactLoad& load);
/// The point a frame records for algorithms without a patch: the plane's, while there is one.
[[nodiscard]] inline Vec3 plane_frame_point(const LocalContact& contact) {
  return contact.valid ? contact.point : Vec3::Zero();
}

}  // namespace tactus::haptics
