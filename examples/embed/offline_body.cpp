// One deformable body stepped offline on the calling thread, no loops and no clock: a soft
// cantilever (linear FEM, clamped at one end) under a tip load. It is stepped in time with
// implicit Euler until it settles, then solved statically, and its tip deflection compared
// with Timoshenko beam theory, δ = F·L³/(3·E·I) + F·L/(κ·G·A).
// Usage: offline_body [steps]   (default 50 steps of 10 ms)
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>

#include "compile/bodies.hpp"  // compile::make_physics_body, assemble_loads: scene body → physics
#include "physics/body.hpp"    // physics::Body, BodyState, step, solve_static
#include "scene/scene.hpp"     // scene::parse_scene

using namespace tactus;

// The body as scene text (docs/scene-format.md); scene::load_scene reads the same from a file.
constexpr const char* kScene = R"(
[scene]
gravity = [0.0, 0.0, 0.0]

[materials.rubber]
model = "linear"
young_modulus = 1.0e6          # Pa
poisson_ratio = 0.3
density = 1000.0               # kg/m^3
damping = { rayleigh_alpha = 20.0 }

# L = 0.1 m, 10 mm x 10 mm section, centred on the origin; 12 cells through the height, since
# linear tetrahedra are too stiff in bending when few (docs/validation-fem.md)
[bodies.beam]
kind = "fem"
material = "rubber"
mesh = { generator = "box", size = [0.1, 0.01, 0.01], cells = [80, 2, 12] }
solver = "cholesky"

[[bodies.beam.fixed]]
side = "x_min"

[[bodies.beam.loads]]          # spread over the nodes of the end face
side = "x_max"
force = [0.0, 0.0, -0.001]     # N
)";

int main(int argc, char** argv) {
  try {
    const scene::Model model = scene::parse_scene(kScene, "beam.toml");
    const scene::Body& beam = model.bodies.at(0);

    // The physics body (force model, fixed dofs, integrator settings) and its rest state.
    const physics::Body body = compile::make_physics_body(model, 0);
    physics::BodyState state = physics::make_state(body);

    // The node nearest the centre of the free end: where the deflection is read.
    const Vec3 tip(0.05, 0.0, 0.0);
    std::size_t tip_node = 0;
    for (std::size_t n = 0; n < beam.volume->vertices.size(); ++n)
      if ((beam.volume->vertices[n] - tip).norm() < (beam.volume->vertices[tip_node] - tip).norm()) tip_node = n;
    const double rest_z = state.x[3 * tip_node + 2];

    // The scene's loads as one external force vector (3 entries a node), fully applied.
    VecX loads(state.x.size());
    compile::assemble_loads(beam, [](double /*ramp_time*/) { return 1.0; }, loads);

    // Dynamics: the load is applied at once, the beam swings and its damping settles it.
    const int steps = argc > 1 ? std::atoi(argv[1]) : 50;
    if (steps < 1) {
      std::fprintf(stderr, "usage: offline_body [steps >= 1]\n");
      return 1;
    }
    const double dt = 0.01;  // [s]
    for (int i = 1; i <= steps; ++i) {
      physics::step(body, state, dt, loads);
      if (i % 10 == 0 || i == steps)
        std::printf("t = %.2f s: tip displacement %.4f mm\n", state.time, 1e3 * (state.x[3 * tip_node + 2] - rest_z));
    }

    // Statics: Newton to equilibrium from where the dynamics left the beam.
    const physics::StaticResult result = physics::solve_static(body, state, loads);
    const double deflection = -(state.x[3 * tip_node + 2] - rest_z);

    // Timoshenko's beam: bending (I = a⁴/12) plus shear (Cowper's κ for a square section).
    const double force = 0.001, length = 0.1, side = 0.01, young = 1.0e6, poisson = 0.3;
    const double bending = force * std::pow(length, 3) / (3.0 * young * std::pow(side, 4) / 12.0);
    const double kappa = 10.0 * (1.0 + poisson) / (12.0 + 11.0 * poisson);
    const double shear = force * length / (kappa * young / (2.0 * (1.0 + poisson)) * side * side);
    std::printf("static tip deflection %.4f mm (%s in %d iterations); Timoshenko %.4f mm; ratio %.3f\n",
                1e3 * deflection, result.converged ? "converged" : "NOT converged", result.iterations,
                1e3 * (bending + shear), deflection / (bending + shear));
    return result.converged ? 0 : 1;
  } catch (const std::exception& e) {  // a bad scene names its file, line and reason
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
