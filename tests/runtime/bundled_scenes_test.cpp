// Every bundled scene with a device runs its first 0.1 s in lockstep with finite forces and
// positions: a scene that diverges at once (an explicit step too long for its springs) fails
// here, not in a user's first run.
#include <gtest/gtest.h>

#include <filesystem>

#include "runtime/session.hpp"
#include "scene/scene.hpp"

namespace tactus {
namespace {

namespace fs = std::filesystem;

TEST(BundledScenes, EveryOneWithADeviceRunsItsFirstTenthOfASecond) {
  int ran = 0;
  for (const auto& entry : fs::directory_iterator(fs::path(TACTUS_SOURCE_DIR) / "scenes")) {
    if (entry.path().extension() != ".toml") continue;
    SCOPED_TRACE(entry.path().filename().string());
    const scene::Model m = scene::load_scene(entry.path());
    if (m.devices.empty()) continue;  // solved by `tactus solve`, not run
    runtime::SessionOptions o;
    o.scheduling = runtime::Scheduling::lockstep;
    o.duration = 0.1;
    o.keep_frames = true;
    runtime::SessionReport r;
    ASSERT_NO_THROW(r = runtime::run_session(m, o));
    EXPECT_GE(r.simulated_time, 0.1 - 1e-9);
    for (const runtime::HapticFrame& f : r.frames) {
      ASSERT_TRUE(f.force.allFinite() && f.proxy.allFinite()) << f.t;
      ASSERT_LE(f.force.norm(), m.devices[f.device].max_force) << f.t;
    }
    ++ran;
  }
  EXPECT_GE(ran, 10);
}

}  // namespace
}  // namespace tactus
