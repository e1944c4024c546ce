#pragma once
// Restriction of the dynamics to a region around a contact (seed 000 §3.3: "reduce the order
// of the dynamic computing by approximately fixing the vertices far from the acting forces").
#include <cstdint>
#include <vector>

#include "physics/body.hpp"
#include "physics/mass_spring/spring_network.hpp"

namespace tactus::physics {

/// Nodes (ascending) whose position in x lies farther than radius from center: the set to
/// fix. Pass the current positions so the region follows the deformed body.
std::vector<std::int32_t> nodes_outside_radius(const VecX& x, const Vec3& center, double radius);

/// The body with the nodes outside the region fixed (in addition to those the full body
/// fixes) and its model reduced to the springs that still move, which is where the time is
/// saved. Call again as the contact moves, then rebind_state.
Body restrict_to_region(const Body& full, const SpringNetwork& network, const VecX& x, const Vec3& center,
                        double radius);

/// Makes a state usable with another body over the same nodes (new model scratch, solver
/// buffers rebuilt for the new fixed set); positions, velocities and history are kept.
void rebind_state(const Body& body, BodyState& state);

}  // namespace tactus::physics
