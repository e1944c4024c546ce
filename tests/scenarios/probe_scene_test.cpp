// The bundled scenes/liver_probe.toml end to end: `tactus precompute` builds its probe space
// (9 leans of up to 10 degrees), and a lockstep run renders the leaning probe from it at
// 1 kHz: in contact from the landing on, smooth, within the device's limit, and the lean
// changes what the hand feels.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "runtime/session.hpp"
#include "scene/scene.hpp"

namespace tactus {
namespace {

namespace fs = std::filesystem;

TEST(ProbeScene, TheBuiltProbeSpaceRendersTheLeaningProbe) {
  const fs::path dir = fs::temp_directory_path() / ("tactus_probe_scene_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path scene = fs::path(TACTUS_SOURCE_DIR) / "scenes/liver_probe.toml";
  const std::string cmd = "cd '" + dir.string() + "' && CI=1 '" + TACTUS_BINARY + "' -q precompute '" +
                          scene.string() + "' -o liver_probe.h5 --threads 2 > log.txt 2>&1";
  const int status = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "tactus precompute failed; see " << dir / "log.txt";
  // The scene with its organ rendered from the space, as `tactus run --space` makes it.
  std::ofstream(dir / "run.toml") << "[scene]\nbase = \"" << scene.string() << "\"\n\n[bodies.liver]\nkind = "
                                  << "\"cspace\"\nspace = \"" << (dir / "liver_probe.h5").string()
                                  << "\"\ninterpolation = \"tricubic_hermite\"\n";
  const scene::Model m = scene::load_scene(dir / "run.toml");
  runtime::SessionOptions o;
  o.scheduling = runtime::Scheduling::lockstep;
  o.keep_frames = true;
  const runtime::SessionReport r = runtime::run_session(m, o);
  fs::remove_all(dir);
  ASSERT_EQ(r.devices.size(), 1u);
  EXPECT_EQ(r.devices[0].safety.clamped, 0u);
  EXPECT_EQ(r.devices[0].safety.non_finite, 0u);
  ASSERT_GT(r.frames.size(), 6900u);  // the 7 s path at 1 kHz

  double largest_step = 0.0;
  Vec3 upright = Vec3::Zero(), leaning = Vec3::Zero();
  for (std::size_t i = 0; i < r.frames.size(); ++i) {
    const runtime::HapticFrame& f = r.frames[i];
    ASSERT_TRUE(f.force.allFinite());
    // The hand starts 1 mm above the organ's top and is on it within 0.15 s; it stays in
    // the grid's box (where the space renders a force) throughout.
    if (f.t > 0.15 && f.t < 6.85) {
      EXPECT_TRUE(f.contact) << "t = " << f.t;
    }
    if (i > 0) largest_step = std::max(largest_step, (f.force - r.frames[i - 1].force).norm());
    if (std::abs(f.t - 1.0) < 1e-9) upright = f.force;  // pressed 6 mm, upright
    if (std::abs(f.t - 2.0) < 1e-9) leaning = f.force;  // the same place, leaning 10° about y
  }
  std::printf("liver_probe from its space: largest step %.3f N; upright %.3f N, leaning (%.3f, %.3f, %.3f) N\n",
              largest_step, upright.norm(), leaning.x(), leaning.y(), leaning.z());
  // No jolt: within the bound every bundled scene keeps (smoothness_test.cpp's kMaxJump).
  EXPECT_LT(largest_step, 1.0);
  // Pressed 6 mm the organ pushes back by more than a newton; leaning the probe changes that
  // by a few per cent (the same position, another configuration).
  EXPECT_GT(upright.z(), 1.0);
  EXPECT_GT((leaning - upright).norm(), 0.02 * upright.norm());
}

}  // namespace
}  // namespace tactus
