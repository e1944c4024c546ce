#pragma once
// One haptic frame of one device as a pure function of its model, its state and the frame's
// inputs: pose → force algorithms → smoothing → passivity → overlays → safety → force written
// → the tissue's reaction. No clock, no allocation, no lock: the schedulers (runtime/) own the
// timing and hand over the channels' newest values as inputs, live edits included.
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "haptics/device.hpp"
#include "haptics/force_algorithm.hpp"
#include "haptics/force_smoothing.hpp"
#include "haptics/passivity_control.hpp"
#include "haptics/safety.hpp"

namespace tactus::haptics {

/// What a device renders, built once from the scene (compile/device_setup.cpp).
struct HapticModel {
  std::uint16_t device = 0;  ///< index into the scene's devices
  double rate = 1000.0;      ///< [Hz]
  WorkspaceMap map;
  /// At most one contact-stage algorithm, then any overlays (ForceAlgorithm::Stage).
  std::vector<std::shared_ptr<const ForceAlgorithm>> algorithms;
  /// Time constant of the passive smoothing of force steps at model updates [s]; 0 = off.
  double force_smoothing = 0.0;
  /// Weaken a contact force that would return more energy to the hand than it put in.
  bool passivity_control = false;
  /// The strongest damping the passivity controller may apply [N·s/m] (the device's).
  double max_damping = 100.0;
  /// Spread the tissue's load over the contact disc instead of the contact triangle.
  bool spread_over_contact_disc = false;
  /// The device of the partner finger whose frames the contact algorithm reads (two-finger
  /// fabric algorithms); none: it has no partner.
  std::optional<std::uint16_t> partner;
  /// Low-pass time constant of the tool velocity estimate [s].
  double velocity_filter = 0.002;
  SafetyConfig safety;

  /// The contact-stage algorithm, or null.
  [[nodiscard]] const ForceAlgorithm* contact() const;
  /// The first algorithm of this class and its index, or null.
  template <class Algorithm>
  [[nodiscard]] const Algorithm* find(std::size_t* index = nullptr) const {
    for (std::size_t i = 0; i < algorithms.size(); ++i)
      if (const auto* a = dynamic_cast<const Algorithm*>(algorithms[i].get())) {
        if (index) *index = i;
        return a;
      }
    return nullptr;
  }
};

/// Everything a device's frames change. Throws std::invalid_argument for a model with two
/// contact-stage algorithms, InputError for a bad safety configuration.
struct HapticState {
  explicit HapticState(const HapticModel& model);
  Vec3 velocity = Vec3::Zero();
  Vec3 last_position = Vec3::Zero();
  double last_t = -1.0;
  ForceSmoother smoother;
  PassivityControl passivity;
  ForceSafety safety;
  std::vector<std::unique_ptr<AlgorithmState>> algorithms;  ///< one per model algorithm
  bool in_contact = false;
  std::uint8_t last_flags = 0;
  std::uint64_t surface_version = 0;  ///< of the last live edit taken
  std::uint8_t contact_state = 0;     ///< the last reported two-finger state (0: none yet)
};

/// A live edit of the contact's coupling (runtime/live_parameters.hpp writes it).
struct SurfaceEdit {
  std::uint64_t version = 0;  ///< 0: none yet
  double from = 0.0;          ///< loop time it applies from [s]
  SurfaceValues values;
  double max_stiffness = 0.0;  ///< the device's [N/m]
};

struct HapticInputs {
  double t = 0.0;
  DevicePose pose;  ///< device coordinates
  bool device_alive = true;
  bool emergency_stop = false;
  const LocalContact* contact = nullptr;  ///< never null
  bool contact_fresh = false;
  const contact::LocalPatch* patch = nullptr;
  /// The patch before `patch`, still held by the channel this frame (null: none).
  const contact::LocalPatch* patch_previous = nullptr;
  bool patch_fresh = false;
  const NeedleSurfaces* surfaces = nullptr;  ///< never null
  bool surfaces_fresh = false;
  const SurfaceEdit* edit = nullptr;  ///< null: no live edits in this run
  const PeerFinger* peer = nullptr;   ///< the partner finger's newest frame; null: no partner
};

/// Where the step writes the force as soon as the safety layer has passed it.
class ForceSink {
 public:
  virtual ~ForceSink() = default;
  virtual void write(const Vec3& force, const Vec3& torque) = 0;
};

struct HapticOutputs {
  SafetyOutput sent;  ///< what was written, device coordinates
  double requested_force = 0.0;  ///< magnitude asked of the safety layer [N]
  bool touching = false;
  Vec3 position = Vec3::Zero();     ///< the tool, scene [m]
  Quat orientation = Quat::Identity();  ///< the tool frame, scene
  Vec3 frame_point = Vec3::Zero();  ///< HapticFrame::proxy
  Vec3 tool_axis = Vec3::Zero();
  PeerFinger finger;  ///< what the partner finger's loop is told about this frame
  /// Where the step writes the tissue's load (the simulation's channel buffer); set before
  /// the first step. Only the fields the load's flags make meaningful are written.
  ContactLoad* load = nullptr;
  static constexpr int kMaxEvents = 8;
  std::array<HapticEvent, kMaxEvents> events{};
  int event_count = 0;
};

void haptic_step(const HapticModel& model, HapticState& state, const HapticInputs& inputs, ForceSink& sink,
                 HapticOutputs& out);

}  // namespace tactus::haptics
