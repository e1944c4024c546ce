#pragma once
// What the loops hand each other, each through its own single-writer single-reader triple
// buffer. All are fixed-size or pre-sized once (surface snapshots), so the haptic loop
// never allocates.
//
//   haptic ──ToolState──▶ interaction ──LocalContact──▶ haptic
//   haptic ──ContactLoad──▶ simulation ──SurfaceSnapshot──▶ interaction, visual
//                           simulation ──NodeSnapshot──▶ recorder (--vtk)
#include <array>
#include <cstdint>
#include <vector>

#include "contact/local_model.hpp"
#include "core/math.hpp"
#include "haptics/exchange.hpp"

namespace tactus::runtime {

/// A device's tool in scene coordinates, as the haptic loop last saw it.
struct ToolState {
  Vec3 position = Vec3::Zero();  ///< tool frame origin (sphere centre for a fingertip)
  Vec3 axis = Vec3::Zero();      ///< needle tools: unit axis towards the tip; zero otherwise
  bool valid = false;
  Quat orientation = Quat::Identity();  ///< tool frame, scene (a probe's lean: cspace bodies)
};

using haptics::ContactLoad;
using haptics::LocalContact;

/// What the simulation builds for a device whose local model is a patch.
struct PatchRequest {
  contact::LocalModelKind kind = contact::LocalModelKind::plane;
  contact::PatchCapacity capacity;
  double radius = 0.0;              ///< of the bounding sphere around the tool origin [m]
  std::vector<std::size_t> bodies;  ///< bodies the device's algorithm touches
};

/// How far a tool strayed from the centre of the patches it was rendered on.
struct PatchReach {
  double max_fraction = 0.0;     ///< largest |tool − centre| / radius over the frames with a patch
  std::uint64_t frames_outside = 0;  ///< frames with the tool beyond its patch's radius
};

/// Deformed surfaces of every body, published after each simulation step.
struct SurfaceSnapshot {
  double t = 0.0;
  std::uint64_t step = 0;
  std::vector<std::vector<Vec3>> positions;  ///< per body, per surface vertex
};

/// Every body's simulation nodes after a step, for the outputs that need more than the
/// surfaces (`tactus run --vtk`). Sized once from the rest state, so the simulation copies
/// into it without allocating.
struct NodeSnapshot {
  double t = 0.0;
  std::uint64_t step = 0;
  std::vector<VecX> x, v;  ///< per body, positions [m] and velocities [m/s], 3 per node
  /// Per body, the devices' contact pushes on each node at the end of the step [N], 3 per
  /// node (the pushes coupled into the step; a needle's shaft push is not included).
  std::vector<VecX> contact;
};

}  // namespace tactus::runtime
