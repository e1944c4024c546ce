// The bundled scenes/liver_pair.toml end to end: `tactus precompute` builds its two-point
// space, and a lockstep run renders both fingers from it at 1 kHz: in contact from the
// landing on, smooth, within the devices' limits, and each finger feels the other's press.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "compile/cspace_body.hpp"
#include "runtime/session.hpp"
#include "scene/scene.hpp"

namespace tactus {
namespace {

namespace fs = std::filesystem;

TEST(PairScene, TheBuiltTwoPointSpaceRendersEachFingerWithTheOthersPress) {
  const fs::path dir = fs::temp_directory_path() / ("tactus_pair_scene_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path scene = fs::path(TACTUS_SOURCE_DIR) / "scenes/liver_pair.toml";
  const std::string cmd = "cd '" + dir.string() + "' && CI=1 '" + TACTUS_BINARY + "' -q precompute '" +
                          scene.string() + "' -o liver_pair.h5 --threads 2 > log.txt 2>&1";
  const int status = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "tactus precompute failed; see " << dir / "log.txt";
  // The scene with its organ rendered from the space, as `tactus run --space` makes it.
  std::ofstream(dir / "run.toml") << "[scene]\nbase = \"" << scene.string() << "\"\n\n[bodies.liver]\nkind = "
                                  << "\"cspace\"\nspace = \"" << (dir / "liver_pair.h5").string()
                                  << "\"\ninterpolation = \"tricubic_hermite\"\n"
                                  << "tools = [\"index_tip\", \"thumb_tip\"]\n";
  const scene::Model m = scene::load_scene(dir / "run.toml");
  const auto body = compile::CspaceBody::load(m, 0);
  ASSERT_NE(body->pair(), nullptr);
  runtime::SessionOptions o;
  o.scheduling = runtime::Scheduling::lockstep;
  o.keep_frames = true;
  const runtime::SessionReport r = runtime::run_session(m, o);
  fs::remove_all(dir);
  ASSERT_EQ(r.devices.size(), 2u);
  std::array<double, 2> largest_step{};
  std::array<Vec3, 2> previous{Vec3::Zero(), Vec3::Zero()};
  Vec3 index_alone = Vec3::Zero(), index_with_thumb = Vec3::Zero(), index_at = Vec3::Zero(), thumb_at = Vec3::Zero();
  std::size_t frames = 0;
  for (const runtime::HapticFrame& f : r.frames) {
    ASSERT_LT(f.device, 2);
    ASSERT_TRUE(f.force.allFinite());
    ++frames;
    // Each finger is in its grid's box (where the space renders a force) from its landing
    // (the grid's top node) until it lifts off: the index 4 mm above from 0 s at 10 mm/s, the
    // thumb 4 mm above from 1 s at 9 mm/s.
    if (f.device == 0 && f.t > 0.41 && f.t < 5.59) {
      EXPECT_TRUE(f.contact) << "index, t = " << f.t;
    }
    if (f.device == 1 && f.t > 1.45 && f.t < 6.05) {
      EXPECT_TRUE(f.contact) << "thumb, t = " << f.t;
    }
    largest_step[f.device] = std::max(largest_step[f.device], (f.force - previous[f.device]).norm());
    previous[f.device] = f.force;
    if (f.device == 0 && std::abs(f.t - 1.0) < 1e-9) index_alone = f.force;       // pressed 6 mm, the thumb up
    if (f.device == 0 && std::abs(f.t - 3.0) < 1e-9) {  // the same place, the thumb in 5 mm
      index_with_thumb = f.force;
      index_at = f.position;
    }
    if (f.device == 1 && std::abs(f.t - 3.0) < 1e-9) thumb_at = f.position;
  }
  ASSERT_GT(frames, 2 * 6400u);  // the 6.5 s paths at 1 kHz
  for (const auto& d : r.devices) {
    EXPECT_EQ(d.safety.clamped, 0u);
    EXPECT_EQ(d.safety.non_finite, 0u);
  }
  std::printf("liver_pair from its space: largest steps %.3f / %.3f N; index %.3f N alone, %.3f N with the thumb in\n",
              largest_step[0], largest_step[1], index_alone.norm(), index_with_thumb.norm());
  // No jolt: within the bound every bundled scene keeps (smoothness_test.cpp's kMaxJump).
  EXPECT_LT(largest_step[0], 1.0);
  EXPECT_LT(largest_step[1], 1.0);
  // Pressed 6 mm the organ pushes the index back; the thumb's 5 mm press 28 mm away changes
  // what it feels (by 8.6 %, 0.69 against 0.64 N, when written; the two points' coupling,
  // docs/validation.md), and the run renders the space's force at the thumb's place.
  EXPECT_GT(index_alone.z(), 0.3);
  EXPECT_GT((index_with_thumb - index_alone).norm(), 0.05 * index_alone.norm());
  const Vec3 expected = body->pair()->force(0, index_at, &thumb_at).force;
  EXPECT_LT((index_with_thumb - expected).norm(), 1e-9 * expected.norm());
}

}  // namespace
}  // namespace tactus
