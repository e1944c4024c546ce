#pragma once
// Simulation bodies built from a scene's Model: the bridge from scene keys to physics models.
#include <memory>

#include "physics/body.hpp"
#include "scene/model.hpp"

namespace tactus::runtime {

/// The physics body of scene body `index`: its force model (FEM, tetrahedral or surface
/// mass-spring, per the body's kind and material), fixed and prescribed nodes as fixed
/// dofs, gravity and step settings. Throws InputError for a rigid body or a combination the
/// physics cannot run (named in the message).
physics::Body make_physics_body(const scene::Model& model, std::size_t index);

}  // namespace tactus::runtime
