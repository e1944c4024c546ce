// Parameters edited during a run (runtime/live_parameters.hpp, the viewer's panel): an edit
// applied at time T acts as if the scene had the new value, the hand-over between threads
// is never torn and allocates nothing on the reading side, bad edits are refused by name.
#include <gtest/gtest.h>

#include <atomic>
#include <functional>
#include <cmath>
#include <string>
#include <thread>

#include "core/error.hpp"
#include "runtime/live_parameters.hpp"
#include "runtime/loop_set.hpp"
#include "scene/scene.hpp"
#include "core/counting_allocator.hpp"

namespace tactus::runtime {
namespace {

std::string replaced(std::string text, const std::string& what, const std::string& with) {
  const auto at = text.find(what);
  EXPECT_NE(at, std::string::npos) << what;
  if (at != std::string::npos) text.replace(at, what.size(), with);
  return text;
}

/// A lockstep run with the loops kept, so that the bodies' final positions can be read.
struct LoopsRun {
  Loops loops;
  SessionReport report;
};

void run(const scene::Model& model, SessionOptions& o, LoopsRun& r, const std::function<void(LiveParameters&)>& edit = {}) {
  o.scheduling = Scheduling::lockstep;
  o.keep_frames = true;
  r.loops = build_loops(model, o);
  if (edit) edit(*o.live);  // after the loops described the devices, before the first step
  // As run_session does: the recorder counts into the devices' reports.
  for (std::size_t i = 0; i < model.devices.size(); ++i)
    r.report.devices.push_back({model.devices[i].name, r.loops.haptic[i]->device().kind(), {}, 0, 0.0, 0});
  Recorder recorder(model, o, r.loops.channel_ptrs(), r.loops.simulation->steps(), r.report);
  run_lockstep(model, o, r.loops, recorder, r.report);
  recorder.close();
}

// --- the haptic side: exact ------------------------------------------------------------------

// The default scene's press: the finger reaches the tissue at t = 0.2 s. An edit of the
// coupling stiffness and friction at t = 0.1 s gives, frame for frame, the run whose scene
// had the new values from the start.
TEST(LiveParameters, SurfaceEditAtTimeTIsTheSceneWithTheNewValues) {
  const std::string base(scene::default_scene_text());
  const scene::Model m = scene::parse_scene(base, "default.toml");
  const scene::Model edited_scene = scene::parse_scene(
      replaced(base, "stiffness = 800.0", "stiffness = 1500.0\nstatic_friction = 0.6\nkinetic_friction = 0.4"),
      "edited.toml");

  LoopsRun edited, reference, unedited;
  {
    LiveParameters live(m);
    SessionOptions o;
    o.duration = 1.0;
    o.live = &live;
    run(m, o, edited, [](LiveParameters& l) {
      ASSERT_EQ(l.surface_kind(0), LiveParameters::SurfaceKind::proxy);
      EXPECT_EQ(l.scene_surface(0).stiffness, 800.0);
      l.set_surface(0, 1500.0, 0.6, 0.4, 0.1);
    });
  }
  {
    LiveParameters live(edited_scene);  // a channel with no edit changes nothing
    SessionOptions o;
    o.duration = 1.0;
    o.live = &live;
    run(edited_scene, o, reference);
  }
  {
    SessionOptions o;
    o.duration = 1.0;
    run(m, o, unedited);
  }
  const auto& a = edited.report.frames;
  const auto& b = reference.report.frames;
  ASSERT_EQ(a.size(), b.size());
  ASSERT_GT(a.size(), 900u);
  std::size_t touching = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a[i].force, b[i].force) << "t = " << a[i].t;
    ASSERT_EQ(a[i].position, b[i].position) << "t = " << a[i].t;
    touching += a[i].contact;
  }
  EXPECT_GT(touching, 500u);
  // And the edit did something: the unedited scene's forces differ once touching.
  double largest_difference = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i)
    largest_difference = std::max(largest_difference, (a[i].force - unedited.report.frames[i].force).norm());
  EXPECT_GT(largest_difference, 0.1);
}

// An edit while touching takes effect in the frame at its time: frames before it are the
// unedited run's, bit for bit, and the first frame at it already feels the stiffer coupling.
TEST(LiveParameters, SurfaceEditWhileTouchingActsInTheNextFrame) {
  const scene::Model m = scene::default_scene();
  LoopsRun edited, unedited;
  {
    LiveParameters live(m);
    SessionOptions o;
    o.duration = 0.8;
    o.live = &live;
    run(m, o, edited, [](LiveParameters& l) { l.set_surface(0, 1600.0, 0.0, 0.0, 0.5); });
  }
  {
    SessionOptions o;
    o.duration = 0.8;
    run(m, o, unedited);
  }
  const auto& a = edited.report.frames;
  const auto& b = unedited.report.frames;
  ASSERT_EQ(a.size(), b.size());
  std::size_t at = 0;
  while (at < a.size() && a[at].t < 0.5) {
    ASSERT_EQ(a[at].force, b[at].force) << "t = " << a[at].t;
    ++at;
  }
  ASSERT_LT(at, a.size());
  ASSERT_TRUE(a[at].contact) << "the press was meant to touch by t = 0.5 s";
  // Twice the coupling stiffness on the same stretch (the proxy and the device have not moved
  // yet): the first edited frame's force is near twice the unedited one.
  EXPECT_NEAR(a[at].force.norm(), 2.0 * b[at].force.norm(), 0.05 * b[at].force.norm()) << "t = " << a[at].t;
}

TEST(LiveParameters, EmergencyStopFromAnotherThreadStopsTheForce) {
  const scene::Model m = scene::default_scene();
  LiveParameters live(m);
  SessionOptions o;
  o.duration = 1.0;
  o.live = &live;
  LoopsRun r;
  run(m, o, r, [](LiveParameters& l) { l.request_emergency_stop(); });
  for (const HapticFrame& f : r.report.frames) {
    ASSERT_EQ(f.force, Vec3::Zero()) << "t = " << f.t;
    ASSERT_TRUE(f.flags & frame_emergency_stop);
  }
  EXPECT_EQ(r.report.events.at("emergency_stop"), 1u);
}

// --- the material: the static dent under a constant load --------------------------------------

// A block under a constant load on its top, the finger far above. Linear elasticity: the
// static dent is inversely proportional to E at a fixed Poisson ratio.
std::string loaded_block(const std::string& model_kind, const std::string& material_model) {
  std::string text(scene::default_scene_text());
  text = replaced(text, "gravity = [0.0, 0.0, -9.81]", "gravity = [0.0, 0.0, 0.0]");
  text = replaced(text, "model = \"corotational\"", "model = \"" + material_model + "\"");
  text = replaced(text, "damping = { rayleigh_alpha = 0.5, rayleigh_beta = 0.005 }",
                  "damping = { rayleigh_alpha = 20.0, rayleigh_beta = 0.002 }");
  text = replaced(text, "kind = \"fem\"", "kind = \"" + model_kind + "\"");
  text = replaced(text, "[devices.hand]",
                  "[[bodies.block.loads]]\nname = \"weight\"\nside = \"z_max\"\nforce = [0.0, 0.0, -2.0]\n\n"
                  "[devices.hand]");
  text = replaced(text, "position = [0.0, 0.0, 0.03]", "position = [0.0, 0.0, 0.12]");
  text = replaced(text, "depth = 0.01", "depth = 0.001");
  return text;
}

double largest_dent(const LoopsRun& r, const scene::Model& m) {
  const VecX* x = r.loops.simulation->positions(0);
  const auto& rest = m.bodies[0].simulation_vertices();
  double dent = 0.0;
  for (std::size_t n = 0; n < rest.size(); ++n) dent = std::max(dent, rest[n].z() - (*x)[static_cast<Eigen::Index>(3 * n + 2)]);
  return dent;
}

void check_material_edit(const std::string& model_kind, const std::string& material_model, double tolerance,
                         bool linear_law) {
  SCOPED_TRACE(model_kind + " / " + material_model);
  const std::string text = loaded_block(model_kind, material_model);
  const scene::Model soft = scene::parse_scene(text, "soft.toml");
  const scene::Model stiff = scene::parse_scene(replaced(text, "young_modulus = 30e3", "young_modulus = 60e3"), "stiff.toml");

  // E doubled at t = 1 s (the dent has settled at the soft value), 2 s more to settle again.
  LoopsRun edited, soft_run, stiff_run;
  double soft_at_edit = 0.0;
  {
    LiveParameters live(soft);
    SessionOptions o;
    o.duration = 3.0;
    o.live = &live;
    run(soft, o, edited, [](LiveParameters& l) { l.set_material(0, 60e3, -1.0, 1.0); });
  }
  {
    SessionOptions o;
    o.duration = 2.0;
    run(soft, o, soft_run);
    soft_at_edit = largest_dent(soft_run, soft);
  }
  {
    SessionOptions o;
    o.duration = 2.0;
    run(stiff, o, stiff_run);
  }
  const double stiff_dent = largest_dent(stiff_run, stiff), edited_dent = largest_dent(edited, soft);
  ASSERT_GT(soft_at_edit, 1e-5);
  EXPECT_NEAR(edited_dent, stiff_dent, tolerance * stiff_dent);
  // Linear elasticity: twice the modulus, half the dent (spring networks and corotational
  // FEM are geometrically nonlinear: about 1 % off at this load).
  if (linear_law) {
    EXPECT_NEAR(stiff_dent, 0.5 * soft_at_edit, tolerance * stiff_dent);
  }
}

TEST(LiveParameters, MaterialEditConvergesToTheNewStaticDent) {
  check_material_edit("fem", "linear", 0.005, true);
  check_material_edit("fem", "corotational", 0.01, false);
  check_material_edit("tet_mass_spring", "linear", 0.01, false);
}

// The damping replaces the scene's mass-proportional damping: the same motion, to round-off,
// as a scene with that damping (lumped mass). Small steps, so that the integrator's own
// damping does not hide the material's.
TEST(LiveParameters, DampingEditIsTheSceneWithThatDamping) {
  const std::string text = replaced(loaded_block("fem", "linear"), "time_step = 0.01", "time_step = 0.0005");
  const scene::Model m = scene::parse_scene(text, "a.toml");
  const scene::Model other = scene::parse_scene(
      replaced(text, "rayleigh_alpha = 20.0", "rayleigh_alpha = 300.0"), "b.toml");
  LoopsRun edited, reference, unedited;
  {
    LiveParameters live(m);
    EXPECT_DOUBLE_EQ(live.scene_materials().body[0].damping, 20.0);
    SessionOptions o;
    o.duration = 0.03;
    o.live = &live;
    run(m, o, edited, [](LiveParameters& l) { l.set_material(0, 30e3, 300.0); });
  }
  SessionOptions o;
  o.duration = 0.03;
  run(other, o, reference);
  run(m, o, unedited);
  const VecX& a = *edited.loops.simulation->positions(0);
  const VecX& b = *reference.loops.simulation->positions(0);
  const VecX& c = *unedited.loops.simulation->positions(0);
  const double motion = largest_dent(reference, other);
  ASSERT_GT(motion, 1e-6);
  EXPECT_LT((a - b).lpNorm<Eigen::Infinity>(), 1e-9 * motion + 1e-15);
  EXPECT_GT((c - b).lpNorm<Eigen::Infinity>(), 1e-3 * motion) << "the damping was meant to matter";
}

// --- errors and the hand-over -----------------------------------------------------------------

TEST(LiveParameters, BadEditsAreRefusedByName) {
  const scene::Model m = scene::default_scene();
  LiveParameters live(m);
  EXPECT_THROW(live.set_material(0, -1.0, -1.0), InputError);
  EXPECT_THROW(live.set_material(5, 1e4, -1.0), InputError);
  // Surfaces are known once a run's loops are built.
  EXPECT_THROW(live.set_surface(0, 500.0, 0.0, 0.0), InputError);
  SessionOptions o;
  o.live = &live;
  Loops loops = build_loops(m, o);
  EXPECT_NO_THROW(live.set_surface(0, 500.0, 0.5, 0.2));
  EXPECT_THROW(live.set_surface(0, 5000.0, 0.0, 0.0), InputError);  // above max_stiffness 2000
  EXPECT_THROW(live.set_surface(0, 500.0, 0.2, 0.5), InputError);   // μk > μs
  try {
    live.set_material(0, std::nan(""), -1.0);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("block"), std::string::npos) << e.what();
  }
}

// One writer (the window) and a reader (a haptic loop): every value read is one that was
// stored whole, and the reader allocates nothing. LoopsRun under ThreadSanitizer by the tsan preset.
TEST(LiveParameters, HandOverBetweenThreadsIsNeverTorn) {
  const scene::Model m = scene::default_scene();
  LiveParameters live(m);
  SessionOptions o;
  o.live = &live;
  Loops loops = build_loops(m, o);
  std::atomic<bool> done{false};
  std::thread writer([&] {
    for (int k = 1; k <= 100000; ++k) {
      live.set_surface(0, 1.0 + (k % 1000), 0.001 * (k % 1000), 0.0005 * (k % 1000));
      live.set_material(0, 1e3 * (1 + k % 1000), 0.01 * (k % 1000));
    }
    done.store(true);
  });
  std::uint64_t torn = 0, reads = 0;
  const tactus::testing::AllocationCounter allocations;
  while (!done.load()) {
    const LiveParameters::Surface s = live.surface(0);
    const LiveParameters::Materials mat = live.materials();
    if (s.version > 0) {
      const double j = s.stiffness - 1.0;
      torn += (s.static_friction != 0.001 * j || s.kinetic_friction != 0.0005 * j) ? 1 : 0;
    }
    if (mat.version > 0) {
      const double j = mat.body[0].young_modulus / 1e3 - 1.0;
      torn += (mat.body[0].damping != 0.01 * j || !mat.body[0].damping_set) ? 1 : 0;
    }
    ++reads;
  }
  EXPECT_EQ(allocations.count(), 0u);
  writer.join();
  EXPECT_EQ(torn, 0u) << "of " << reads << " reads";
  EXPECT_EQ(live.surface(0).version, 100000u);
}

}  // namespace
}  // namespace tactus::runtime
