// The bundled scenes/room.toml end to end: the scripted hand presses every object it is meant
// to (the kettle, the teapot, the F-shape, the dragon, the bunny, the table's varnish strip and
// felt pad, and the sofa's FEM cushion through the contact plane), never beyond the device's
// limit; a second fingertip presses the F and the bunny with the Hertz law; the touched
// objects' impostor levels switch and each switch is recorded.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>
#include <string>

#include "contact/bvh.hpp"
#include "runtime/session.hpp"
#include "scene/scene.hpp"

namespace tactus {
namespace {

namespace fs = std::filesystem;

TEST(RoomScene, TheHandPressesEveryObjectAndTheLevelsFollow) {
  const scene::Model m = scene::load_scene(fs::path(TACTUS_SOURCE_DIR) / "scenes/room.toml");
  runtime::SessionOptions o;
  o.scheduling = runtime::Scheduling::lockstep;
  o.keep_frames = true;
  const runtime::SessionReport r = runtime::run_session(m, o);
  ASSERT_EQ(r.devices.size(), 2u);
  for (const auto& d : r.devices) {
    EXPECT_EQ(d.safety.clamped, 0u) << d.name;
    EXPECT_EQ(d.safety.non_finite, 0u) << d.name;
    EXPECT_LT(d.max_force_sent, 8.0) << d.name;
  }

  // Which body each contact frame's point lies on (within 2 mm of its rest surface).
  std::vector<contact::TriangleBvh> trees;
  for (const auto& b : m.bodies) trees.emplace_back(b.surface.vertices, b.surface.triangles);
  std::map<std::string, int> frames_on, index_on;
  for (const auto& f : r.frames) {
    if (!f.contact) continue;
    std::size_t best = 0;
    double nearest = 1e9;
    for (std::size_t b = 0; b < trees.size(); ++b) {
      const double d = trees[b].closest_point(f.proxy).distance;
      if (d < nearest) nearest = d, best = b;
    }
    if (nearest < 0.002) ++(f.device == 0 ? frames_on : index_on)[m.bodies[best].name];
  }
  for (const char* name : {"kettle", "teapot", "f_shape", "dragon", "bunny", "table", "cushion"})
    EXPECT_GT(frames_on[name], 100) << name;
  for (const char* name : {"f_shape", "bunny"}) EXPECT_GT(index_on[name], 100) << "index on " << name;

  // The levels: every object the hand came near had its level chosen; the dragon and the
  // bunny, near each other, were given finer and coarser levels as the hand moved between them.
  std::set<std::string> switched;
  std::map<std::string, std::set<std::uint32_t>> levels;
  for (const auto& s : r.level_switches) {
    ASSERT_GE(s.body, 0);
    switched.insert(m.bodies[static_cast<std::size_t>(s.body)].name);
    levels[m.bodies[static_cast<std::size_t>(s.body)].name].insert(s.level);
  }
  for (const char* name : {"kettle", "teapot", "dragon", "bunny"}) EXPECT_TRUE(switched.count(name)) << name;
  EXPECT_GE(levels["dragon"].size(), 2u);
  EXPECT_GE(levels["bunny"].size(), 2u);

  // A switch while the hand presses moves the force by at most 10 % of its value from one
  // frame to the next, over the switch and its blend (the press itself changes it far less).
  std::vector<runtime::HapticFrame> hand;  // the hand's frames, one a millisecond
  for (const auto& f : r.frames)
    if (f.device == 0) hand.push_back(f);
  int pressed_switches = 0;
  double worst = 0.0;
  for (const auto& s : r.level_switches) {
    const auto at = static_cast<std::size_t>(std::lround(s.t * 1000.0));
    if (s.device != 0 || at == 0 || at + 8 >= hand.size() || !hand[at].contact) continue;
    ++pressed_switches;
    for (std::size_t k = at; k <= at + 7; ++k) {
      const double now = hand[k].force.norm(), before = hand[k - 1].force.norm();
      if (now > 0.2) worst = std::max(worst, std::abs(now - before) / now);
    }
  }
  std::printf("room: %d switches while pressing, largest force step across one %.1f %%\n", pressed_switches, 100 * worst);
  EXPECT_GE(pressed_switches, 1);
  EXPECT_LE(worst, 0.10);
}

}  // namespace
}  // namespace tactus
