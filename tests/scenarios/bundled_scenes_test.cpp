// Every bundled scene with a device runs its first 0.1 s in lockstep with finite forces and
// positions: a scene that diverges at once (an explicit step too long for its springs) fails
// here, not in a user's first run.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "report/report.hpp"
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

// The needle block's lockstep report was said to print an empty "parts" table: every part
// its loops time is listed with its times (lockstep measures compute time as real time does).
TEST(BundledScenes, NeedleBlockLockstepReportListsEveryPartItTimes) {
  const scene::Model m = scene::load_scene(fs::path(TACTUS_SOURCE_DIR) / "scenes" / "needle_block.toml");
  runtime::SessionOptions o;
  o.scheduling = runtime::Scheduling::lockstep;
  const runtime::SessionReport r = runtime::run_session(m, o);
  const std::string text = report::format_report(r);
  const std::size_t table = text.find("\nparts ");
  ASSERT_NE(table, std::string::npos) << text;
  const std::string parts = text.substr(table, text.find("\n\n", table + 1) - table);
  for (const char* part : {"haptic[hand]: device read -> force written", "simulation: contact loads",
                           "simulation: integrate", "simulation: shaft node search", "interaction: refit trees"}) {
    SCOPED_TRACE(part);
    const std::size_t at = parts.find(part);
    ASSERT_NE(at, std::string::npos) << parts;
    const std::string row = parts.substr(at, parts.find('\n', at) - at);
    EXPECT_EQ(row.find(" - "), std::string::npos) << "a part without times: " << row;
  }
}

}  // namespace
}  // namespace tactus
