#pragma once
// A scene body's nodules (seed 004) as the physics enforces them.
#include "physics/nodules.hpp"
#include "scene/model.hpp"

namespace tactus::compile {

/// The body's nodules with the area each surface node stands for: a rigid nodule stays
/// rigid; a soft one gets its Hertz pressure coefficient from its Young's modulus, Poisson
/// ratio and radius (physics::hertz_pressure_coefficient). Empty when it has none.
physics::NoduleSet physics_nodules(const scene::Body& body);

}  // namespace tactus::compile
