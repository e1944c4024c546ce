// The simulation step driven by hand, with no loop: the first step publishes the rest
// shapes, a push with its slope ends where tissue and contact balance, material edits are
// inputs, and the parts are timed only with a clock given.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <utility>
#include <vector>

#include "core/counting_allocator.hpp"  // tests/core
#include "runtime/simulation_step.hpp"
#include "scene/scene.hpp"

namespace tactus::runtime {
namespace {

const scene::Model& block() {
  static const scene::Model m =
      scene::load_scene(std::filesystem::path(TACTUS_SOURCE_DIR) / "tests/fixtures/scenes/soft_block.toml");
  return m;
}

/// The top-surface triangle whose centroid is nearest the top's centre.
std::int32_t top_centre_triangle() {
  const scene::Body& b = block().bodies.front();
  std::int32_t best = -1;
  double best_d = 1e9;
  for (std::size_t t = 0; t < b.surface.triangles.size(); ++t) {
    Vec3 c = Vec3::Zero();
    for (auto v : b.surface.triangles[t]) c += b.surface.vertices[v] / 3.0;
    if (const double d = c.norm(); d < best_d) best_d = d, best = static_cast<std::int32_t>(t);
  }
  return best;
}

ContactLoad press(double force, double stiffness) {
  ContactLoad load;
  load.active = true;
  load.body = 0;
  load.triangle = top_centre_triangle();
  load.barycentric = Vec3::Constant(1.0 / 3.0);
  load.force = Vec3(0, 0, -force);
  load.stiffness = stiffness;
  load.contact_radius = -1.0;
  return load;
}

/// How far the top's centre has sunk after steps at `periods` (in periods; the first step
/// publishes the rest shape) under `load` [m].
double sinking_at(const SimulationModel& model, SimulationState& state, const ContactLoad& load,
                  const std::vector<int>& periods, const LiveParameters::Materials* edits = nullptr,
                  const LiveParameters::Materials* scene = nullptr) {
  SurfaceSnapshot surfaces = rest_surfaces(model);
  SurfaceSnapshot* outputs[] = {&surfaces};
  const std::array<ContactLoad, 1> loads{load};
  const std::array<ToolState, 1> tools{};
  contact::LocalPatch* patches[] = {nullptr};
  for (const int k : periods) {
    SimulationInputs in;
    in.t = k * model.period;
    in.loads = loads;
    in.materials = edits;
    in.scene_materials = scene;
    (void)advance_bodies(model, state, in, {});
    publish_shapes(model, state, in, tools, {outputs, patches, {}});
  }
  const auto& rest = block().bodies.front().surface.vertices;
  std::size_t centre = 0;
  for (std::size_t v = 1; v < rest.size(); ++v)
    if (rest[v].norm() < rest[centre].norm()) centre = v;
  return rest[centre].z() - surfaces.positions[0][centre].z();
}

/// The same after `steps` steps on time.
double sinking(const SimulationModel& model, SimulationState& state, const ContactLoad& load, int steps,
               const LiveParameters::Materials* edits = nullptr, const LiveParameters::Materials* scene = nullptr) {
  std::vector<int> periods(static_cast<std::size_t>(steps));
  for (int k = 0; k < steps; ++k) periods[static_cast<std::size_t>(k)] = k;
  return sinking_at(model, state, load, periods, edits, scene);
}

TEST(SimulationStep, TheFirstStepPublishesTheRestShapes) {
  const SimulationModel model = make_simulation_model(block(), {std::nullopt});
  SimulationState state = make_simulation_state(model);
  const std::array<ContactLoad, 1> loads{press(1.0, 0.0)};
  SimulationInputs in;
  in.loads = loads;
  EXPECT_EQ(advance_bodies(model, state, in, {}), 0);
  SurfaceSnapshot surfaces = rest_surfaces(model);
  for (auto& p : surfaces.positions[0]) p = Vec3::Constant(1.0);
  SurfaceSnapshot* outputs[] = {&surfaces};
  const std::array<ToolState, 1> tools{};
  contact::LocalPatch* patches[] = {nullptr};
  publish_shapes(model, state, in, tools, {outputs, patches, {}});
  EXPECT_EQ(surfaces.step, 0u);
  EXPECT_EQ(surfaces.positions[0], block().bodies[0].surface.vertices);
  EXPECT_EQ(state.step, 1u);
}

TEST(SimulationStep, APushWithItsSlopeGivesWayAsTheTissueDoes) {
  // 2 N held constant against 2 N from a 300 N/m contact that eases as the tissue yields:
  // the coupled push ends lower than it started, and the tissue sinks less.
  const SimulationModel model = make_simulation_model(block(), {std::nullopt});
  SimulationState constant = make_simulation_state(model), coupled = make_simulation_state(model);
  const double held = sinking(model, constant, press(2.0, 0.0), 2);
  const double eased = sinking(model, coupled, press(2.0, 300.0), 2);
  EXPECT_GT(eased, 0.0);
  EXPECT_LT(eased, held);
  ASSERT_EQ(coupled.devices[0].spring, 0);
  const physics::ContactSpring& spring = coupled.bodies[0].springs[0];
  EXPECT_LT(spring.force_end, 2.0);
  EXPECT_GT(spring.force_end, 0.0);
  EXPECT_EQ(constant.bodies[0].springs[0].force_end, 2.0);
}

// In real time the simulation may step again before the haptic loop renders on the surface
// it published. A push rendered on an older surface is eased by its slope times how far the
// contact point has moved along it since: the step goes as with that eased push rendered on
// the surface it starts from (where, as in lockstep, nothing is eased).
TEST(SimulationStep, APushRenderedOnAnOlderSurfaceEasesByHowFarThePointHasMovedSince) {
  PatchRequest request;
  request.kind = contact::LocalModelKind::compliance;
  request.radius = 0.01;
  request.bodies = {0};
  const SimulationModel model = make_simulation_model(block(), {request});
  const scene::Body& body = block().bodies.front();
  const ContactLoad pressing = press(2.0, 300.0);
  const mesh::Triangle& corners = body.surface.triangles[static_cast<std::size_t>(pressing.triangle)];
  const Vec3 at_rest = mesh::point_on(body.surface.vertices, corners, pressing.barycentric);

  // Three pressed steps, then one more with `load`: the push at its end and the top's sinking.
  const auto step_with = [&](const std::function<ContactLoad(const Vec3& now)>& load_for) {
    SimulationState state = make_simulation_state(model);
    (void)sinking(model, state, pressing, 3);
    const Vec3 now = mesh::point_on(state.bodies[0].surface, corners, pressing.barycentric);
    const double sunk = sinking_at(model, state, load_for(now), {3});
    return std::pair{state.bodies[0].springs[0].force_end, sunk};
  };
  double moved = 0.0;
  const auto rendered_at_rest = step_with([&](const Vec3& now) {
    moved = (now - at_rest).dot(Vec3(0, 0, -1));  // along the push
    ContactLoad load = pressing;
    load.published_point = at_rest;
    return load;
  });
  ASSERT_GT(moved, 1e-5);
  const auto eased_on_now = step_with([&](const Vec3& now) {
    ContactLoad load = press(2.0 - 300.0 * moved, 300.0);
    load.published_point = now;
    return load;
  });
  const auto taken_as_it_came = step_with([&](const Vec3&) { return pressing; });
  EXPECT_NEAR(rendered_at_rest.first, eased_on_now.first, 1e-12);
  EXPECT_NEAR(rendered_at_rest.second, eased_on_now.second, 1e-15);
  EXPECT_GT(taken_as_it_came.first, rendered_at_rest.first + 0.5 * 300.0 * moved);
}

/// A pad of a pinch over the block's top, 5 mm into it (radius 20 mm: the block's nodes are
/// 10 mm apart), the pinch's plane 3 mm below the top, its partner below.
struct PadOverTheTop {
  double top = -1e9;
  double radius = 0.02;
  ContactLoad::Pad pad;
  PadOverTheTop() {
    for (const Vec3& v : block().bodies.front().surface.vertices) top = std::max(top, v.z());
    const Vec3 centre(0, 0, top + radius - 5e-3);
    pad = {true, centre, centre, radius, Vec3(0, 0, top - 3e-3), Vec3(0, 0, -1)};
  }
  /// How deep `p` lies in the pad on the pad's side of the plane (≤ 0: out of it).
  [[nodiscard]] double inside(const Vec3& p) const {
    return std::min(pad.toward_partner.dot(pad.plane_point - p), radius - (p - pad.base).norm());
  }
};

/// The body's nodes at the corners of the load's triangle.
std::vector<Eigen::Index> corner_nodes(const SimulationModel& model, const ContactLoad& load) {
  std::vector<Eigen::Index> nodes;
  for (const auto v : block().bodies.front().surface.triangles[static_cast<std::size_t>(load.triangle)])
    nodes.push_back(model.bodies[0].surface_to_node[static_cast<std::size_t>(v)]);
  return nodes;
}

// After two steps no node lies in the pad on its side of the plane (but the held point's
// corners, which the hold's spring places). Nodes near the pad's centre land on the plane, the
// others on the pad's sphere.
TEST(SimulationStep, AGraspingPadKeepsTheBodysNodesOutOfIt) {
  const SimulationModel model = make_simulation_model(block(), {std::nullopt});
  SimulationState state = make_simulation_state(model);
  const PadOverTheTop over;
  ContactLoad load = press(0.0, 0.0);
  // The held point on the bottom, out of the pad's way.
  const auto& rest = block().bodies.front().surface.vertices;
  const auto& triangles = block().bodies.front().surface.triangles;
  const auto centroid_z = [&](std::size_t t) {
    return (rest[triangles[t][0]].z() + rest[triangles[t][1]].z() + rest[triangles[t][2]].z()) / 3.0;
  };
  for (std::size_t t = 0; t < triangles.size(); ++t)
    if (centroid_z(t) < centroid_z(static_cast<std::size_t>(load.triangle)))
      load.triangle = static_cast<std::int32_t>(t);
  load.pad = over.pad;
  const physics::BodyState& nodes = state.bodies[0].state;
  const std::vector<Eigen::Index> held = corner_nodes(model, load);
  int in_at_rest = 0;
  for (Eigen::Index i = 0; i < nodes.x.size() / 3; ++i)
    in_at_rest += over.inside(nodes.x.segment<3>(3 * i)) > 1e-4 ? 1 : 0;
  ASSERT_GT(in_at_rest, 3);
  (void)sinking(model, state, load, 2);
  int on_plane = 0, on_sphere = 0;
  for (Eigen::Index i = 0; i < nodes.x.size() / 3; ++i) {
    if (std::find(held.begin(), held.end(), i) != held.end()) continue;
    const Vec3 p = nodes.x.segment<3>(3 * i);
    EXPECT_LE(over.inside(p), 1e-12) << "node " << i;
    if (std::abs(p.z() - (over.top - 3e-3)) < 1e-12) ++on_plane;
    if (std::abs((p - over.pad.base).norm() - over.radius) < 1e-12) ++on_sphere;
  }
  EXPECT_GT(on_plane, 0);
  EXPECT_GT(on_sphere, 0);
}

// The held point's corners are the hold's springs' to place: a pad over the held triangle
// (the top's centre) leaves its corners in the pad where the step put them, and moves the
// top's other nodes in the pad out of it.
TEST(SimulationStep, AGraspingPadLeavesTheHeldTrianglesCornersToTheHold) {
  const SimulationModel model = make_simulation_model(block(), {std::nullopt});
  SimulationState state = make_simulation_state(model);
  const PadOverTheTop over;
  ContactLoad load = press(0.0, 0.0);  // the top's centre triangle held
  load.pad = over.pad;
  const std::vector<Eigen::Index> corners = corner_nodes(model, load);
  const physics::BodyState& nodes = state.bodies[0].state;
  std::vector<Eigen::Index> others_inside;
  for (Eigen::Index i = 0; i < nodes.x.size() / 3; ++i) {
    const bool corner = std::find(corners.begin(), corners.end(), i) != corners.end();
    if (!corner && over.inside(nodes.x.segment<3>(3 * i)) > 1e-4) others_inside.push_back(i);
  }
  ASSERT_FALSE(others_inside.empty());
  (void)sinking(model, state, load, 2);
  for (const Eigen::Index i : corners) EXPECT_GT(over.inside(nodes.x.segment<3>(3 * i)), 1e-3) << "held corner " << i;
  for (const Eigen::Index i : others_inside) EXPECT_LE(over.inside(nodes.x.segment<3>(3 * i)), 1e-12) << "node " << i;
}

// A grasp's hold along the pads' plane (the block's top) pulls along +x; a push along +y on
// the same point stands for the sheet dragging it sideways. As two springs in the plane the
// hold resists that drag as well, pulling back along −y; along its force alone the point
// slid sideways freely during the step.
TEST(SimulationStep, AHoldAlongAPlaneHoldsThePointAcrossItsForceToo) {
  const SimulationModel model = make_simulation_model(block(), {std::nullopt, std::nullopt});
  const scene::Body& body = block().bodies.front();
  const std::int32_t triangle = top_centre_triangle();
  const mesh::Triangle& corners = body.surface.triangles[static_cast<std::size_t>(triangle)];
  const Vec3 at_rest = mesh::point_on(body.surface.vertices, corners, Vec3::Constant(1.0 / 3.0));
  const auto run = [&](const Vec3& plane_normal, const Vec3& hold) {
    ContactLoad holding = press(0.0, 3000.0);
    holding.force = hold;
    holding.hold_plane_normal = plane_normal;
    ContactLoad drag = press(0.0, 0.0);
    drag.force = Vec3(0, 0.3, 0);
    const std::array<ContactLoad, 2> loads{holding, drag};
    SimulationState state = make_simulation_state(model);
    for (int k = 0; k < 4; ++k) {
      SimulationInputs in;
      in.t = k * model.period;
      in.loads = loads;
      (void)advance_bodies(model, state, in, {});
      SurfaceSnapshot surfaces = rest_surfaces(model);
      SurfaceSnapshot* outputs[] = {&surfaces};
      const std::array<ToolState, 2> tools{};
      contact::LocalPatch* patches[] = {nullptr, nullptr};
      publish_shapes(model, state, in, tools, {outputs, patches, {}});
    }
    return state;
  };
  const SimulationState along_force = run(Vec3::Zero(), Vec3(0.2, 0, 0));
  const SimulationState in_plane = run(Vec3(0, 0, 1), Vec3(0.2, 0, 0));
  ASSERT_EQ(along_force.devices[0].spring_count, 1);
  ASSERT_EQ(in_plane.devices[0].spring_count, 2);
  const auto& springs = in_plane.bodies[0].springs;
  ASSERT_EQ(springs.size(), 3u);  // the hold's two, the drag's one
  EXPECT_NEAR(springs[0].direction.dot(Vec3(1, 0, 0)), 1.0, 1e-12);
  EXPECT_NEAR(std::abs(springs[1].direction.dot(Vec3(0, 1, 0))), 1.0, 1e-12);
  EXPECT_TRUE(springs[0].bilateral && springs[1].bilateral);
  const double pull_back = springs[1].force_end * springs[1].direction.y();
  EXPECT_LT(pull_back, -0.05);
  EXPECT_GT(pull_back, -0.3);
  const auto sideways = [&](const SimulationState& state) {
    return (mesh::point_on(state.bodies[0].surface, corners, Vec3::Constant(1.0 / 3.0)) - at_rest).y();
  };
  EXPECT_GT(sideways(along_force), 0.0);
  EXPECT_LT(sideways(in_plane), 0.5 * sideways(along_force));
  // A hold with no force in the plane still holds the point there.
  const SimulationState unloaded = run(Vec3(0, 0, 1), Vec3::Zero());
  ASSERT_EQ(unloaded.devices[0].spring_count, 2);
  EXPECT_LT(sideways(unloaded), 0.5 * sideways(along_force));
}

TEST(SimulationStep, MaterialEditsAreInputsFromTheirTime) {
  // The block twice as stiff by an edit sinks about half as far under the same push (small
  // strains of a corotational body: linear in E); an edit dated later is not applied yet.
  const SimulationModel model = make_simulation_model(block(), {std::nullopt});
  const LiveParameters live(block());
  SimulationState scene_state = make_simulation_state(model, &live), edited_state = make_simulation_state(model, &live),
                  later_state = make_simulation_state(model, &live);
  LiveParameters::Materials edits = live.scene_materials(), later = live.scene_materials();
  edits.version = later.version = 1;
  edits.body[0].young_modulus = later.body[0].young_modulus = 2.0 * live.scene_materials().body[0].young_modulus;
  later.from = 10.0;
  const double soft = sinking(model, scene_state, press(0.2, 0.0), 60);
  const double stiff = sinking(model, edited_state, press(0.2, 0.0), 60, &edits, &live.scene_materials());
  const double not_yet = sinking(model, later_state, press(0.2, 0.0), 60, &later, &live.scene_materials());
  EXPECT_NEAR(stiff / soft, 0.5, 0.02);
  EXPECT_EQ(not_yet, soft);
  EXPECT_EQ(edited_state.materials_version, 1u);
  EXPECT_EQ(later_state.materials_version, 0u);
}

TEST(SimulationStep, ALateStepSpansTheMissedPeriodsUpToCatchUp) {
  // A real-time step after two missed periods: with catch_up 3 the block advances over the
  // three periods (one longer implicit step) and ends nearer the block stepped on time than
  // the same step with catch_up 1, which advances one period and lets the body fall behind.
  scene::Model catching_up = block();
  catching_up.rates.catch_up = 3.0;
  const SimulationModel model = make_simulation_model(block(), {std::nullopt});
  const SimulationModel late_model = make_simulation_model(catching_up, {std::nullopt});
  SimulationState on_time = make_simulation_state(model), behind = make_simulation_state(model),
                  caught_up = make_simulation_state(late_model);
  const double expected = sinking_at(model, on_time, press(1.0, 0.0), {0, 1, 2, 3, 4});
  const double one_period = sinking_at(model, behind, press(1.0, 0.0), {0, 1, 4});
  const double spanned = sinking_at(late_model, caught_up, press(1.0, 0.0), {0, 1, 4});
  std::printf("sunk on time %.4f mm, one period late %.4f mm, spanning the late periods %.4f mm\n", 1e3 * expected,
              1e3 * one_period, 1e3 * spanned);
  EXPECT_GT(expected, 0.0);
  EXPECT_LT(std::abs(spanned - expected), 0.5 * std::abs(one_period - expected));
  EXPECT_EQ(on_time.late_steps, 0u);
  EXPECT_EQ(behind.late_steps, 0u);
  EXPECT_EQ(caught_up.late_steps, 1u);
  EXPECT_DOUBLE_EQ(caught_up.bodies[0].span, 3 * model.period);
  // Later than catch_up periods, it spans catch_up of them; on time, one period exactly.
  SimulationState later = make_simulation_state(late_model);
  (void)sinking_at(late_model, later, press(1.0, 0.0), {0, 1, 9, 10});
  EXPECT_EQ(later.late_steps, 1u);
  EXPECT_DOUBLE_EQ(later.bodies[0].span, late_model.period);
}

Nanos fake_clock() {
  static Nanos t = 0;
  return t += 1000;
}

TEST(SimulationStep, PartsAreTimedOnlyWithTheLoopsClock) {
  const SimulationModel model = make_simulation_model(block(), {std::nullopt});
  SimulationState state = make_simulation_state(model);
  std::vector<PartStats> parts(simulation_part_count);
  SurfaceSnapshot surfaces = rest_surfaces(model);
  SurfaceSnapshot* outputs[] = {&surfaces};
  const std::array<ContactLoad, 1> loads{press(1.0, 100.0)};
  const std::array<ToolState, 1> tools{};
  contact::LocalPatch* patches[] = {nullptr};
  for (const bool timed : {false, true}) {
    SimulationInputs in;
    in.loads = loads;
    in.clock = timed ? fake_clock : nullptr;
    in.start = timed ? fake_clock() : 0;
    (void)advance_bodies(model, state, in, parts);
    publish_shapes(model, state, in, tools, {outputs, patches, parts});
    if (!timed) {
      for (const PartStats& p : parts) EXPECT_EQ(p.time.count(), 0u);
    }
  }
  // The second step (the first advances nothing) timed its loads, integration and surfaces.
  EXPECT_EQ(parts[contact_loads].time.count(), 1u);
  EXPECT_EQ(parts[integrate].time.count(), 1u);
  EXPECT_EQ(parts[publish_surfaces].time.count(), 1u);
  EXPECT_EQ(parts[local_models].time.count(), 0u);  // no patch device
}

TEST(SimulationStep, NodeSnapshotsHoldTheStateAndThePushWithoutAllocating) {
  // What `--vtk` reads: positions, velocities and each node's share of the contact push,
  // written into a snapshot sized once (the simulation thread allocates nothing for it).
  const SimulationModel model = make_simulation_model(block(), {std::nullopt});
  SimulationState state = make_simulation_state(model);
  (void)sinking(model, state, press(2.0, 300.0), 3);
  NodeSnapshot nodes = rest_nodes(model);
  const testing::AllocationCounter counter;
  write_nodes(model, state, 0.25, nodes);
  EXPECT_EQ(counter.count(), 0u);
  EXPECT_EQ(nodes.t, 0.25);
  EXPECT_EQ(nodes.x[0], state.bodies[0].state.x);
  EXPECT_EQ(nodes.v[0], state.bodies[0].state.v);
  // The pushes on the nodes add up to the spring's push at the end of the step (its shares
  // sum to one), along its direction.
  ASSERT_EQ(state.bodies[0].springs.size(), 1u);
  const physics::ContactSpring& spring = state.bodies[0].springs[0];
  Vec3 total = Vec3::Zero();
  std::size_t pushed = 0;
  for (Eigen::Index n = 0; n < nodes.contact[0].size() / 3; ++n) {
    total += nodes.contact[0].segment<3>(3 * n);
    pushed += nodes.contact[0].segment<3>(3 * n).norm() > 0.0;
  }
  EXPECT_GT(pushed, 1u);
  EXPECT_GT(spring.force_end, 0.0);
  EXPECT_LT((total - spring.force_end * spring.direction).norm(), 1e-12 * spring.force_end);
}

}  // namespace
}  // namespace tactus::runtime
