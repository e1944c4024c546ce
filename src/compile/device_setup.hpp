#pragma once
// What a device's haptic loop renders, compiled from the scene: the force algorithms of the
// tool it drives, the bodies they touch, the local model and the safety limits.
#include <cstddef>
#include <vector>

#include "contact/local_model.hpp"
#include "haptics/haptic_step.hpp"
#include "compile/cspace_body.hpp"
#include "compile/touchables.hpp"
#include "scene/model.hpp"

namespace tactus::compile {

struct DeviceSetup {
  haptics::HapticModel model;
  /// The device's tool touches the scene (the interaction loop looks for its contacts).
  bool renders = false;
  /// The local model between simulation steps: the plane, or a patch of this kind and capacity
  /// that the simulation publishes on the device's channels.
  contact::LocalModelKind local_model = contact::LocalModelKind::plane;
  contact::PatchCapacity patch_capacity;
  std::vector<std::size_t> bodies;  ///< bodies the device's algorithm touches
  double reach = 0.0;               ///< surfaces farther than this from the tool give no contact [m]
  int curvature_rings = 0;          ///< q-ring of the curvature vote; 0 = none needed
  /// Radius of the local patch's bounding sphere around the tool origin (patch models) [m].
  double patch_radius = 0.0;
  /// > 0: the device drives a needle this long, or casts a multi_surface ray from this far
  /// behind the tool; `bodies` are its layers [m].
  double needle_length = 0.0;
};

/// Device limits (force, stiffness, workspace) from the scene.
haptics::DeviceLimits device_limits(const scene::Device& device);
/// Device → scene mapping from the scene's scale, rotation and offset.
haptics::WorkspaceMap workspace_map(const scene::Device& device);

/// The straight insertion line a scripted needle follows (in device coordinates), if any.
const scene::NeedleLinePath* needle_line(const scene::Device& device);

/// Throws InputError for a tool or algorithm the runtime cannot render yet. `touchables`:
/// the scene's touchable objects, shared by its devices (null: built for this device alone
/// where its algorithm touches any).
DeviceSetup setup_device(const scene::Model& model, std::size_t device, const CspaceBodies& cspaces = {},
                         const Touchables* touchables = nullptr);

}  // namespace tactus::compile
