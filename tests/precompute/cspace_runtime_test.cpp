// A scene body of kind "cspace": `tactus run`'s loops render the force from a precomputed
// space at haptic rate, publish its interpolated shape, and refuse a space of another body.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>
#include <array>
#include <chrono>
#include <thread>
#include <memory>
#include <string>
#include <utility>

#include "core/error.hpp"
#include "precompute/interpolator.hpp"
#include "precompute/pair.hpp"
#include "precompute/space_file.hpp"
#include "compile/cspace_body.hpp"
#include "report/report.hpp"
#include "runtime/session.hpp"
#include "scene/scene.hpp"
#include "test_body.hpp"

namespace tactus::precompute {
namespace {

namespace fs = std::filesystem;

/// A scripted fingertip pressing 4 mm down from the block's contact point (the grid's
/// start) and holding.
const std::string kPressingHand = R"(
[devices.hand]
type = "scripted"
max_force = 10.0

[devices.hand.trajectory]
type = "press"
position = [0.001, 0.0005, 0.01]
direction = [0.0, 0.0, -1.0]
depth = 0.004
speed = 0.02
hold = 0.1

[tools.finger]
type = "sphere"
device = "hand"
radius = 0.004

[algorithms.touch]
type = "proxy"
tool = "finger"
stiffness = 1000.0
)";

/// The block's body as a cspace body, pressed by kPressingHand.
std::string run_scene(const std::string& interpolation, double young = 5.0e3) {
  std::string body = testing::block_scene("");
  body = body.substr(0, body.find("[precompute]"));
  const std::string fem = "kind = \"fem\"";
  body.replace(body.find(fem), fem.size(),
               "kind = \"cspace\"\nspace = \"space.h5\"\ninterpolation = \"" + interpolation + "\"");
  const std::string modulus = "young_modulus = 5.0e3";
  body.replace(body.find(modulus), modulus.size(), "young_modulus = " + std::to_string(young));
  return body + kPressingHand;
}

class CspaceRuntime : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("tactus_cspace_runtime_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
    std::ofstream(dir_ / "block.toml") << testing::block_scene(R"(contact_point = [0.0, 0.0, 0.01]
spacing = 0.003
min = [-0.006, -0.006, 0.001]
max = [0.006, 0.006, 0.013]
)");
    const std::string cmd = "cd '" + dir_.string() + "' && CI=1 '" + TACTUS_BINARY +
                            "' -q precompute block.toml -o space.h5 --threads 2 >log.txt 2>&1";
    const int status = std::system(cmd.c_str());
    ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "tactus precompute failed";
  }
  void TearDown() override { fs::remove_all(dir_); }

  /// Exit code of `tactus -q ARGS` run in the test's folder, its output appended to log.txt.
  int tactus(const std::string& args) {
    const std::string cmd = "cd '" + dir_.string() + "' && CI=1 '" + TACTUS_BINARY + "' -q " + args + " >>log.txt 2>&1";
    const int status = std::system(cmd.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  std::string log() const {
    std::ifstream in(dir_ / "log.txt");
    return std::string(std::istreambuf_iterator<char>(in), {});
  }

  scene::Model model(const std::string& text) {
    std::ofstream(dir_ / "run.toml") << text;
    return scene::load_scene(dir_ / "run.toml");
  }

  fs::path dir_;
};

/// Every frame's force is finite, and every frame the safety layer left alone rendered what
/// `lookup` gives for it (a valid query); `compared` counts those frames.
template <class Lookup>
void expect_frames_render(const runtime::SessionReport& r, Lookup lookup, std::size_t& compared) {
  for (const runtime::HapticFrame& f : r.frames) {
    ASSERT_TRUE(f.force.allFinite());
    if (f.flags != 0) continue;  // the safety layer changed this frame's force
    const Query q = lookup(f);
    ASSERT_TRUE(q.valid) << "t = " << f.t;
    EXPECT_LT((f.force - q.force).norm(), 1e-12 + 1e-9 * q.force.norm())
        << "t = " << f.t << ": " << f.force.transpose() << " against " << q.force.transpose();
    ++compared;
  }
}

TEST_F(CspaceRuntime, LockstepRunRendersTheInterpolatedForce) {
  for (const char* method : {"trilinear", "rbf_cubic"}) {
    SCOPED_TRACE(method);
    const scene::Model m = model(run_scene(method));
    ASSERT_TRUE(m.bodies.front().cspace);
    runtime::SessionOptions o;
    o.scheduling = runtime::Scheduling::lockstep;
    o.duration = 0.35;
    o.keep_frames = true;
    const runtime::SessionReport r = runtime::run_session(m, o);
    ASSERT_GT(r.frames.size(), 300u);

    const Interpolator direct(std::make_shared<const Space>(read_space(dir_ / "space.h5")),
                              parse_interpolation(method));
    std::size_t compared = 0;
    ASSERT_NO_FATAL_FAILURE(
        expect_frames_render(r, [&](const runtime::HapticFrame& f) { return direct.force(f.position); }, compared));
    EXPECT_GT(compared, 300u);
    double deepest_force = 0.0;
    for (const runtime::HapticFrame& f : r.frames)
      if (f.flags == 0) deepest_force = std::max(deepest_force, f.force.z());
    // 4 mm into the block it pushes back up.
    EXPECT_GT(deepest_force, 0.05);
  }
}

TEST_F(CspaceRuntime, AProbeSpaceRendersTheForceAndTorqueOfTheToolsLean) {
  // A probe space of the block (9 leans of up to 12 degrees), and a hand that presses 2.5 mm
  // while its −z axis leans 10 degrees about y.
  std::ofstream(dir_ / "probe.toml") << testing::probe_block_scene();
  ASSERT_EQ(tactus("precompute probe.toml -o probe.h5 --threads 2"), 0) << log();
  std::string text = run_scene("tricubic_hermite");
  text.replace(text.find("space.h5"), 8, "probe.h5");
  const std::string press = text.substr(text.find("[devices.hand.trajectory]"));
  text.replace(text.find(press), press.find("[tools.finger]"), R"([devices.hand.trajectory]
type = "waypoints"
points = [
  { time = 0.0, position = [0.001, 0.0005, 0.0099], direction = [0.0, 0.0, -1.0] },
  { time = 0.3, position = [0.001, 0.0005, 0.0075], direction = [0.17364817766693033, 0.0, -0.984807753012208] },
]

)");
  const scene::Model m = model(text);
  const auto body = compile::CspaceBody::load(m, 0);
  ASSERT_NE(body->probe(), nullptr);
  EXPECT_EQ(body->probe()->level_count(), 9u);

  runtime::SessionOptions o;
  o.scheduling = runtime::Scheduling::lockstep;
  o.duration = 0.4;
  o.keep_frames = true;
  const runtime::SessionReport r = runtime::run_session(m, o);
  ASSERT_GT(r.frames.size(), 350u);
  std::size_t compared = 0;
  ASSERT_NO_FATAL_FAILURE(expect_frames_render(
      r,
      [&](const runtime::HapticFrame& f) {
        return body->probe()->force(f.position, compile::CspaceBody::probe_direction(f.orientation));
      },
      compared));
  EXPECT_GT(compared, 350u);
  // Held leaning at the end: the force is the leaning probe's, not the upright one's. The
  // lean about y (the frame's tilt along x) sets a sideways force the upright probe lacks.
  const runtime::HapticFrame& last = r.frames.back();
  const Vec3 upright = body->probe()->force(last.position, Vec3(0, 0, -1)).force;
  EXPECT_GT((last.force - upright).norm(), 0.05 * upright.norm()) << last.force.transpose() << " / "
                                                                    << upright.transpose();
  // The torque on the probe about its end (the point looked up is the tool's origin here).
  for (const runtime::HapticFrame& f : r.frames) {
    if (f.flags != 0) continue;
    const Query q = body->probe()->force_and_torque(f.position, compile::CspaceBody::probe_direction(f.orientation));
    EXPECT_LT((f.torque - q.torque).norm(), 1e-15 + 1e-9 * q.torque.norm()) << "t = " << f.t;
  }
  EXPECT_GT(last.torque.norm(), 1e-4) << last.torque.transpose();
}

/// The block as a cspace body of the two-point space `space`, felt by two scripted fingers,
/// each on its own device, pressing at the two points (`tools`: the body's key, or empty).
std::string pair_run_scene(const std::string& space, const std::string& tools) {
  std::string text = testing::block_scene("");
  text = text.substr(0, text.find("[precompute]"));
  const std::string fem = "kind = \"fem\"";
  text.replace(text.find(fem), fem.size(),
               "kind = \"cspace\"\nspace = \"" + space + "\"\ninterpolation = \"tricubic_hermite\"\n" + tools);
  auto finger = [](const std::string& name, const std::string& at, double depth, double speed) {
    return "[devices." + name + "]\ntype = \"scripted\"\nmax_force = 10.0\n\n[devices." + name +
           ".trajectory]\ntype = \"press\"\nposition = " + at + "\ndirection = [0.0, 0.0, -1.0]\ndepth = " +
           std::to_string(depth) + "\nspeed = " + std::to_string(speed) + "\nhold = 1.0\n\n[tools." + name +
           "_tip]\ntype = \"sphere\"\ndevice = \"" + name + "\"\nradius = 0.004\n\n[algorithms." + name +
           "_touch]\ntype = \"proxy\"\ntool = \"" + name + "_tip\"\nstiffness = 1000.0\n\n";
  };
  return text + finger("first", "[-0.0098, 0.0005, 0.0100]", 0.004, 0.02) +
         finger("second", "[0.0101, -0.0004, 0.0100]", 0.003, 0.03);
}

TEST_F(CspaceRuntime, ATwoPointSpaceRendersEachFingersForceWithTheOtherFingerWhereItIs) {
  std::ofstream(dir_ / "pair.toml") << testing::pair_block_scene();
  ASSERT_EQ(tactus("precompute pair.toml -o pair.h5 --threads 2"), 0) << log();
  const scene::Model m = model(pair_run_scene("pair.h5", "tools = [\"first_tip\", \"second_tip\"]\n"));
  const auto body = compile::CspaceBody::load(m, 0);
  const PairInterpolator* pair = body->pair();
  ASSERT_NE(pair, nullptr);
  ASSERT_EQ(pair->level_count(), 56u);

  runtime::SessionOptions o;
  o.scheduling = runtime::Scheduling::lockstep;
  o.duration = 0.5;
  o.keep_frames = true;
  const runtime::SessionReport r = runtime::run_session(m, o);
  // Each device's frames by index.
  std::array<std::vector<const runtime::HapticFrame*>, 2> frames;
  for (const runtime::HapticFrame& f : r.frames) {
    ASSERT_LT(f.device, 2);
    ASSERT_TRUE(f.force.allFinite());
    auto& list = frames[f.device];
    if (list.size() <= f.frame) list.resize(f.frame + 1, nullptr);
    list[f.frame] = &f;
  }
  ASSERT_GT(frames[0].size(), 450u);
  ASSERT_GT(frames[1].size(), 450u);
  // Every frame the safety layer left alone renders its point's force with the other finger
  // where the partner's loop last published it: at the same tick or the one before (the
  // lockstep order), or nowhere yet at the start.
  std::size_t compared = 0;
  for (int finger = 0; finger < 2; ++finger)
    for (std::size_t n = 0; n < frames[static_cast<std::size_t>(finger)].size(); ++n) {
      const runtime::HapticFrame* f = frames[static_cast<std::size_t>(finger)][n];
      if (!f || f->flags != 0) continue;
      const auto& other = frames[static_cast<std::size_t>(1 - finger)];
      double best = pair->force(finger, f->position, nullptr).force.isApprox(f->force, 1e-9) ? 0.0 : 1e9;
      for (std::size_t m2 : {n, n - 1})
        if (m2 < other.size() && other[m2]) {
          const Query q = pair->force(finger, f->position, &other[m2]->position);
          best = std::min(best, (q.force - f->force).norm() / (1e-12 + q.force.norm()));
        }
      EXPECT_LT(best, 1e-9) << "finger " << finger << " frame " << n << " t = " << f->t;
      ++compared;
    }
  EXPECT_GT(compared, 900u);
  // Both fingers holding at the end: each feels the other's press (the other finger free would
  // give another force), and its own.
  const Vec3 a = frames[0].back()->position, b = frames[1].back()->position;
  EXPECT_LT(a.z(), 0.0065);
  EXPECT_LT(b.z(), 0.0075);
  const Vec3 alone = pair->force(0, a, nullptr).force, both = pair->force(0, a, &b).force;
  EXPECT_LT((frames[0].back()->force - both).norm(), 1e-9 * both.norm());
  EXPECT_GT((both - alone).norm(), 0.05 * alone.norm()) << both.transpose() << " / " << alone.transpose();
  EXPECT_GT(both.z(), 0.05);
  // The shape holds each point's contact node at its finger.
  VecX x;
  body->positions(&a, &b, x);
  const Space& first = pair->level(0).space();
  EXPECT_LT((x.segment<3>(3 * first.settings.contact_node) - a).norm(), 1e-9);
  EXPECT_LT((x.segment<3>(3 * first.settings.pair.node) - b).norm(), 1e-9);
}

TEST_F(CspaceRuntime, ATwoPointSpaceNeedsItsTwoToolsNamed) {
  std::ofstream(dir_ / "pair.toml") << testing::pair_block_scene();
  ASSERT_EQ(tactus("precompute pair.toml -o pair.h5 --threads 2"), 0) << log();
  auto load_error = [&](const std::string& text) -> std::string {
    try {
      (void)compile::CspaceBody::load(model(text), 0);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  };
  const std::string unnamed = load_error(pair_run_scene("pair.h5", ""));
  EXPECT_NE(unnamed.find("holds two points; name the tools"), std::string::npos) << unnamed;
  const std::string one_point = load_error(pair_run_scene("space.h5", "tools = [\"first_tip\", \"second_tip\"]\n"));
  EXPECT_NE(one_point.find("holds one point"), std::string::npos) << one_point;
  // The scene refuses a tool named twice or one it lacks, by key.
  const std::string twice = load_error(pair_run_scene("pair.h5", "tools = [\"first_tip\", \"first_tip\"]\n"));
  EXPECT_NE(twice.find("tools"), std::string::npos) << twice;
  EXPECT_NE(twice.find("two devices"), std::string::npos) << twice;
  const std::string unknown = load_error(pair_run_scene("pair.h5", "tools = [\"first_tip\", \"thumb\"]\n"));
  EXPECT_NE(unknown.find("thumb"), std::string::npos) << unknown;
}

TEST_F(CspaceRuntime, RunWithSpaceFlagHandsATwoPointSpaceToTheToolsItsTableNames) {
  // The scene the two-point space is built from, its [precompute] table naming the tools at
  // the two points, and the two fingers of pair_run_scene.
  std::string fingers = pair_run_scene("unused.h5", "");
  fingers = fingers.substr(fingers.find("[devices.first]"));
  std::ofstream(dir_ / "pair.toml") << testing::pair_block_scene()
                                    << "interpolation = \"tricubic_hermite\"\ntools = [\"first_tip\", "
                                       "\"second_tip\"]\n\n"
                                    << fingers;
  ASSERT_EQ(tactus("precompute pair.toml -o pair.h5 --threads 2"), 0) << log();
  ASSERT_EQ(tactus("run pair.toml --space pair.h5 --lockstep -d 0.3"), 0) << log();
  // The table's method by default, and both fingers touching.
  EXPECT_NE(log().find("rendered from the configuration space"), std::string::npos) << log();
  EXPECT_NE(log().find("(tricubic_hermite interpolation)"), std::string::npos) << log();
  const std::string text = log();
  for (const char* device : {"first (scripted): max force sent", "second (scripted): max force sent"}) {
    const auto at = text.find(device);
    ASSERT_NE(at, std::string::npos) << text;
    const std::string line = text.substr(at, text.find('\n', at) - at);
    EXPECT_EQ(line.find(" 0 frames in contact"), std::string::npos) << line;
    EXPECT_NE(line.find("clamped 0, non-finite 0"), std::string::npos) << line;
  }
  // Without the table's tools the run names what is missing.
  std::ofstream(dir_ / "unnamed.toml") << testing::pair_block_scene() << "\n" << fingers;
  EXPECT_EQ(tactus("run unnamed.toml --space pair.h5 --lockstep -d 0.1"), 1) << log();
  EXPECT_NE(log().find("name the tools that feel the two points"), std::string::npos) << log();
}

TEST_F(CspaceRuntime, ShapeFollowsTheToolAndForceIsZeroOutsideTheGrid) {
  const scene::Model m = model(run_scene("trilinear"));
  const auto body = compile::CspaceBody::load(m, 0);
  const Space& space = body->interpolator().space();
  VecX x, displacement;
  const Vec3 p(0.001, 0.0005, 0.007);
  body->positions(p, Quat::Identity(), x);
  const Query q = body->interpolator().shape(p, displacement);
  ASSERT_TRUE(q.valid);
  EXPECT_TRUE(x.isApprox(space.rest_positions + displacement, 1e-14));
  // The contact node moves with the interaction point (trilinear is exact for it: every
  // configuration holds it at its grid point).
  const auto n = 3 * static_cast<Eigen::Index>(space.settings.contact_node);
  EXPECT_LT((x.segment<3>(n) - p).norm(), 1e-9);
  EXPECT_FALSE(body->force(Vec3(0.0, 0.0, 0.05), Quat::Identity(), 0.0).touching);
  EXPECT_TRUE(body->force(p, Quat::Identity(), 0.25).touching);
  EXPECT_EQ(body->force(Vec3(0.0, 0.0, 0.05), Quat::Identity(), 0.5).force, Vec3::Zero());
  // Where the tool was is counted, for the run's report: outside twice, inside once, at 0.25 s.
  const compile::CspaceBody::BoxCounts box = body->box_counts();
  EXPECT_EQ(box.inside, 1u);
  EXPECT_EQ(box.outside, 2u);
  EXPECT_EQ(box.first_inside, 0.25);
}

TEST_F(CspaceRuntime, TheReportSaysWhenTheToolWasOutsideTheSpace) {
  // The hand starts 7 mm above the grid's box (its top at z = 13 mm) and enters it after
  // 0.14 s: the run says how long it felt nothing there.
  std::string text = run_scene("trilinear");
  for (const auto& [from, to] : {std::pair<std::string, std::string>{"position = [0.001, 0.0005, 0.01]",
                                                                      "position = [0.001, 0.0005, 0.02]"},
                                 {"depth = 0.004", "depth = 0.011"},
                                 {"speed = 0.02", "speed = 0.05"}})
    text.replace(text.find(from), from.size(), to);
  const scene::Model m = model(text);
  runtime::SessionOptions o;
  o.scheduling = runtime::Scheduling::lockstep;
  o.duration = 0.35;
  const runtime::SessionReport r = runtime::run_session(m, o);
  std::string notes;
  for (const std::string& n : r.cspace_notes) notes += n + "\n";
  EXPECT_NE(notes.find("outside its grid box"), std::string::npos) << notes;
  EXPECT_NE(notes.find("first inside at t = 0.14"), std::string::npos) << notes;
  EXPECT_NE(report::format_report(r).find("outside its grid box"), std::string::npos);
}

TEST_F(CspaceRuntime, RefusesASpaceBuiltForAnotherMaterial) {
  const scene::Model m = model(run_scene("trilinear", 7.0e3));
  try {
    compile::CspaceBody::load(m, 0);
    FAIL() << "a space of another material was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("model hash"), std::string::npos) << e.what();
  }
  // And `tactus run` refuses it before any loop starts.
  runtime::SessionOptions o;
  o.scheduling = runtime::Scheduling::lockstep;
  o.duration = 0.01;
  EXPECT_THROW(runtime::run_session(m, o), InputError);
}

TEST_F(CspaceRuntime, RunWithSpaceFlagFeelsTheSpaceAndReplaysBitForBit) {
  // The scene the space was built from (block.toml, its [precompute] body simulated by
  // default) with a hand: --space renders that body from the space instead.
  std::string scene;
  {
    std::ifstream in(dir_ / "block.toml");
    scene.assign(std::istreambuf_iterator<char>(in), {});
  }
  std::ofstream(dir_ / "hand.toml") << scene + kPressingHand;
  ASSERT_EQ(tactus("run hand.toml --space space.h5 --interpolation rbf_cubic --lockstep -d 0.35 --record run.tactus"),
            0)
      << log();
  EXPECT_NE(log().find("rendered from the configuration space"), std::string::npos) << log();
  ASSERT_EQ(tactus("export run.tactus --csv frames.csv"), 0) << log();

  // Every unclamped frame's force is the space's cubic-RBF force at the finger's centre.
  const Interpolator direct(std::make_shared<const Space>(read_space(dir_ / "space.h5")),
                            Interpolation::rbf_cubic);
  std::ifstream csv(dir_ / "frames.csv");
  std::string line;
  std::getline(csv, line);  // t,device,frame,x,y,z,qw,qx,qy,qz,buttons,fx,fy,fz,...,contact,flags
  std::size_t compared = 0;
  double deepest_force = 0.0;
  while (std::getline(csv, line)) {
    std::vector<std::string> cells;
    std::stringstream row(line);
    for (std::string cell; std::getline(row, cell, ',');) cells.push_back(cell);
    ASSERT_GE(cells.size(), 19u) << line;
    std::vector<double> v(19, 0.0);  // the device column (1) is its name
    for (std::size_t i : {3u, 4u, 5u, 11u, 12u, 13u, 18u}) v[i] = std::stod(cells[i]);
    if (v[18] != 0.0) continue;  // the safety layer changed this frame's force
    const Query q = direct.force(Vec3(v[3], v[4], v[5]));
    ASSERT_TRUE(q.valid) << line;
    // The CSV holds the shortest text that reads back to the same double.
    EXPECT_LT((Vec3(v[11], v[12], v[13]) - q.force).norm(), 1e-12 + 1e-9 * q.force.norm()) << line;
    deepest_force = std::max(deepest_force, v[13]);
    ++compared;
  }
  EXPECT_GT(compared, 300u);
  EXPECT_GT(deepest_force, 0.05);

  // The recording holds a scene that names the space, so its replay renders the same forces.
  ASSERT_EQ(tactus("replay run.tactus"), 0) << log();
  EXPECT_NE(log().find("forces identical bit for bit"), std::string::npos) << log();
}

TEST_F(CspaceRuntime, RunWithSpaceFlagNeedsTheScenesPrecomputeTable) {
  std::string scene = testing::block_scene("");
  scene = scene.substr(0, scene.find("[precompute]"));
  std::ofstream(dir_ / "plain.toml") << scene + kPressingHand;
  EXPECT_EQ(tactus("run plain.toml --space space.h5 --lockstep -d 0.05"), 1);
  EXPECT_NE(log().find("no [precompute] table"), std::string::npos) << log();
  // A space of another material: refused with the difference named, before any loop runs.
  std::string stiffer;
  {
    std::ifstream in(dir_ / "block.toml");
    stiffer.assign(std::istreambuf_iterator<char>(in), {});
  }
  const std::string modulus = "young_modulus = 5.0e3";
  stiffer.replace(stiffer.find(modulus), modulus.size(), "young_modulus = 7.0e3");
  std::ofstream(dir_ / "stiffer.toml") << stiffer + kPressingHand;
  EXPECT_EQ(tactus("run stiffer.toml --space space.h5 --lockstep -d 0.05"), 1);
  EXPECT_NE(log().find("model hash"), std::string::npos) << log();
  // --interpolation is for --space only.
  EXPECT_NE(tactus("run plain.toml --interpolation rbf_cubic --lockstep -d 0.05"), 0);
  EXPECT_NE(log().find("--interpolation requires --space"), std::string::npos) << log();
}

/// block.toml with its [precompute] body built on-line during the run.
std::string online_scene(const std::string& block, const std::string& keys = "online = true\nworkers = 2") {
  std::string text = block;
  const std::string fem = "kind = \"fem\"";
  text.replace(text.find(fem), fem.size(), "kind = \"cspace\"\n" + keys);
  return text;
}

TEST_F(CspaceRuntime, OnlineBodySolvesAroundTheToolAndFeelsWhatTheBuiltSpaceHolds) {
  std::string block;
  {
    std::ifstream in(dir_ / "block.toml");
    block.assign(std::istreambuf_iterator<char>(in), {});
  }
  const scene::Model m = model(online_scene(block));
  std::size_t index = 0;
  while (!m.bodies[index].cspace) ++index;
  const auto body = compile::CspaceBody::load(m, index);
  ASSERT_TRUE(body->online());
  // The tool holds one grid spacing below the contact point, a grid point: once it is solved
  // the force there is that point's, the one the space built before the run holds (the same
  // transition from the same source).
  const Space built = read_space(dir_ / "space.h5");
  const std::array<int, 3> start = built.grid.cell(built.start);
  const std::size_t below = built.grid.index(start[0], start[1], start[2] - 1);
  ASSERT_TRUE(built.solved(below));
  const Vec3 p = built.grid.point(below);
  const Vec3 expected = built.force[below];
  Vec3 last = Vec3::Zero();
  double t = 0.0;
  bool reached = false;
  // Real time: the solvers run beside this loop at 1 kHz (10 s is far more than the few
  // solves this takes, even under a sanitizer).
  for (int frame = 0; frame < 10000 && !reached; ++frame, t += 1e-3) {
    const compile::CspaceForce f = body->force(p, Quat::Identity(), t);
    ASSERT_TRUE(f.force.allFinite());
    EXPECT_LE((f.force - last).norm(), 0.1 + 1e-12) << "frame " << frame;  // OnlineSettings::max_force_step
    last = f.force;
    reached = f.touching && (f.force - expected).norm() <= 1e-9 * expected.norm();
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  ASSERT_TRUE(reached) << "online force " << last.transpose() << " against " << expected.transpose();
  EXPECT_GT(body->solved_points(), 1u);
  // The shape there: the contact node at the tool (every configuration holds it at its
  // grid point).
  VecX x;
  body->positions(p, Quat::Identity(), x);
  const auto n = 3 * static_cast<Eigen::Index>(built.settings.contact_node);
  EXPECT_LT((x.segment<3>(n) - p).norm(), 1e-9);
  // Outside the grid's box the tool is not attached.
  EXPECT_FALSE(body->force(Vec3(0.0, 0.0, 0.05), Quat::Identity(), t).touching);
}

TEST_F(CspaceRuntime, RunWithOnlineFlagBuildsTheSpaceDuringTheRun) {
  std::string block;
  {
    std::ifstream in(dir_ / "block.toml");
    block.assign(std::istreambuf_iterator<char>(in), {});
  }
  std::ofstream(dir_ / "hand.toml") << block + kPressingHand;
  ASSERT_EQ(tactus("run hand.toml --online --online-threads 2 -d 0.5 --priority 0 --cpu -1"), 0) << log();
  EXPECT_NE(log().find("built on-line during the run (2 solver threads)"), std::string::npos) << log();
  EXPECT_NE(log().find("grid points solved during the run"), std::string::npos) << log();
  // Not with a space file, not without a [precompute] table, and a scene says one or the other.
  EXPECT_NE(tactus("run hand.toml --online --space space.h5 --lockstep -d 0.05"), 0);
  std::string plain = testing::block_scene("");
  plain = plain.substr(0, plain.find("[precompute]"));
  std::ofstream(dir_ / "plain.toml") << plain + kPressingHand;
  EXPECT_EQ(tactus("run plain.toml --online --lockstep -d 0.05"), 1);
  EXPECT_NE(log().find("--online: this scene has no [precompute] table"), std::string::npos) << log();
  try {
    (void)model(online_scene(block, "online = true\nspace = \"space.h5\""));
    FAIL() << "a body with both online and space loaded";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("either `space` or `online = true`"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace tactus::precompute
