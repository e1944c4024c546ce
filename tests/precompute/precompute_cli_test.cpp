// `tactus precompute` end to end: a build, a build stopped and resumed, and (with MPI) a
// build over three ranks, all giving the same space.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "precompute/space_file.hpp"
#include "test_body.hpp"

namespace tactus::precompute {
namespace {

namespace fs = std::filesystem;

const std::string kScene = testing::block_scene(R"(contact_point = [0.0, 0.0, 0.01]
spacing = 0.003
min = [-0.003, -0.003, 0.004]
max = [0.003, 0.003, 0.013]
)");

class PrecomputeCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("tactus_precompute_cli_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
    std::ofstream(dir_ / "block.toml") << kScene;
  }
  void TearDown() override { fs::remove_all(dir_); }

  /// Exit code of `[launcher] tactus -q precompute block.toml -o OUT args`.
  int precompute(const std::string& out, const std::string& args, const std::string& launcher = "") {
    const std::string cmd = "cd '" + dir_.string() + "' && CI=1 " + launcher + " '" + TACTUS_BINARY +
                            "' -q precompute block.toml -o " + out + " " + args + " >>log.txt 2>&1";
    const int status = std::system(cmd.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  std::string log() const {
    std::ifstream in(dir_ / "log.txt");
    return std::string(std::istreambuf_iterator<char>(in), {});
  }

  static void expect_same(const Space& a, const Space& b) {
    EXPECT_EQ(a.status, b.status);
    EXPECT_EQ(a.source, b.source);
    EXPECT_EQ(a.force, b.force);
    EXPECT_TRUE(a.displacement == b.displacement);
    EXPECT_EQ(a.identity.model_hash, b.identity.model_hash);
  }

  fs::path dir_;
};

TEST_F(PrecomputeCli, BuildsTheSpace) {
  ASSERT_EQ(precompute("space.h5", "--threads 2"), 0) << log();
  EXPECT_FALSE(fs::exists(dir_ / "space.h5.journal"));
  const Space s = read_space(dir_ / "space.h5");
  EXPECT_EQ(s.grid.size(), 36u);
  EXPECT_EQ(s.count(PointStatus::solved), 36u);
  EXPECT_NE(s.scene_text.find("[precompute]"), std::string::npos);
}

TEST_F(PrecomputeCli, RefinePointsSplitsCellsAfterTheBuild) {
  std::ofstream(dir_ / "block.toml", std::ios::app) << "refine_points = 25\n";
  ASSERT_EQ(precompute("space.h5", "--threads 2"), 0) << log();
  // 25 points: 5 cells' centres probed, then one split of 18 points more.
  EXPECT_NE(log().find("refined 1 cells: 23 points more (0 not solved)"), std::string::npos) << log();
  const Space s = read_space(dir_ / "space.h5");
  EXPECT_EQ(s.settings.refine_points, 25);
  EXPECT_EQ(s.point_count(), 36u + 23u);
  EXPECT_EQ(s.refined_cells.size(), 1u);
  EXPECT_EQ(s.count(PointStatus::solved), 59u);
}

TEST_F(PrecomputeCli, FailureSummaryGivesTheNumbersAndTheGridPoint) {
  // One Newton iteration to 1e-14 never converges: every transition fails, and the summary
  // must say how (load step, residual, iterations) and where, not "load step #/#".
  const std::string failing = testing::block_scene(R"(contact_point = [0.0, 0.0, 0.01]
spacing = 0.003
min = [-0.003, -0.003, 0.004]
max = [0.003, 0.003, 0.013]
load_steps = 2
max_iterations = 1
max_step_halvings = 0
tolerance = 1e-14
)");
  std::ofstream(dir_ / "failing.toml") << failing;
  const std::string cmd = "cd '" + dir_.string() + "' && CI=1 '" + TACTUS_BINARY +
                          "' precompute failing.toml -o failing.h5 --threads 1 >>log.txt 2>&1";
  (void)std::system(cmd.c_str());
  const std::string text = log();
  const auto at = text.find("load step");
  ASSERT_NE(at, std::string::npos) << text;
  const std::string line = text.substr(text.rfind('\n', at) + 1, text.find('\n', at) - text.rfind('\n', at) - 1);
  EXPECT_EQ(line.find('#'), std::string::npos) << line;
  EXPECT_NE(line.find("load step 1/2"), std::string::npos) << line;
  EXPECT_NE(line.find("at grid point ("), std::string::npos) << line;
  EXPECT_NE(line.find(" mm"), std::string::npos) << line;
}

TEST_F(PrecomputeCli, ResumeAfterAStopComputesNothingTwiceAndLosesNothing) {
  ASSERT_EQ(precompute("whole.h5", "--threads 1"), 0) << log();
  // Stopped after 10 solves: the journal stays, no space file yet.
  ASSERT_EQ(precompute("part.h5", "--threads 1 --stop-after 10"), 3) << log();
  EXPECT_TRUE(fs::exists(dir_ / "part.h5.journal"));
  EXPECT_FALSE(fs::exists(dir_ / "part.h5"));
  // Without --resume the journal is not silently overwritten.
  EXPECT_EQ(precompute("part.h5", "--threads 1"), 1);
  EXPECT_NE(log().find("--resume"), std::string::npos);
  // Append half a record, as a kill in mid-write would.
  { std::ofstream(dir_ / "part.h5.journal", std::ios::app | std::ios::binary) << "TPCR"; }
  ASSERT_EQ(precompute("part.h5", "--threads 2 --resume"), 0) << log();
  EXPECT_FALSE(fs::exists(dir_ / "part.h5.journal"));
  const Space whole = read_space(dir_ / "whole.h5");
  const Space part = read_space(dir_ / "part.h5");
  expect_same(whole, part);
}

const std::string kProbeScene = testing::probe_block_scene();

void expect_same_levels(const fs::path& a, const fs::path& b) {
  const std::vector<Space> x = read_space_levels(a), y = read_space_levels(b);
  ASSERT_EQ(x.size(), 9u);
  ASSERT_EQ(y.size(), x.size());
  for (std::size_t k = 0; k < x.size(); ++k) {
    SCOPED_TRACE("level " + std::to_string(k));
    EXPECT_EQ(x[k].settings.tilt, y[k].settings.tilt);
    EXPECT_EQ(x[k].count(PointStatus::solved), x[k].grid.size());
    EXPECT_EQ(x[k].status, y[k].status);
    EXPECT_EQ(x[k].force, y[k].force);
    // The torques and their derivatives travel with the forces (MPI, the journal).
    EXPECT_EQ(x[k].torque, y[k].torque);
    EXPECT_EQ(x[k].torque_gradient, y[k].torque_gradient);
    EXPECT_TRUE(x[k].displacement == y[k].displacement);
    EXPECT_EQ(x[k].identity.model_hash, y[k].identity.model_hash);
  }
  // A leaning probe's end turns the block: its torques are not zero, so the above compares.
  EXPECT_GT(x.back().torque[x.back().start].norm(), 1e-4);
}

TEST_F(PrecomputeCli, AProbeSpaceIsBuiltLevelByLevelAndResumesAtTheLevelItStoppedIn) {
  std::ofstream(dir_ / "block.toml") << kProbeScene;
  ASSERT_EQ(precompute("whole.h5", "--threads 2"), 0) << log();
  EXPECT_NE(log().find("level 9 of 9: the probe leaning 12.0, 12.0 degrees"), std::string::npos) << log();
  // Stopped after 10 solves of its first level.
  ASSERT_EQ(precompute("part.h5", "--threads 1 --stop-after 10"), 3) << log();
  EXPECT_TRUE(fs::exists(dir_ / "part.h5.level-0.journal"));
  EXPECT_FALSE(fs::exists(dir_ / "part.h5"));
  // Resumed with a stop after 20 solves a level: the first level's last 17 are solved, the
  // second level stops, and both levels' journals stay.
  ASSERT_EQ(precompute("part.h5", "--threads 1 --resume --stop-after 20"), 3) << log();
  EXPECT_TRUE(fs::exists(dir_ / "part.h5.level-0.journal"));
  EXPECT_TRUE(fs::exists(dir_ / "part.h5.level-1.journal"));
  EXPECT_FALSE(fs::exists(dir_ / "part.h5.level-2.journal"));
  ASSERT_EQ(precompute("part.h5", "--threads 2 --resume"), 0) << log();
  EXPECT_NE(log().find("(27 taken from the journal)"), std::string::npos) << log();
  EXPECT_NE(log().find("(20 taken from the journal)"), std::string::npos) << log();
  for (int k = 0; k < 9; ++k) EXPECT_FALSE(fs::exists(dir_ / ("part.h5.level-" + std::to_string(k) + ".journal")));
  expect_same_levels(dir_ / "whole.h5", dir_ / "part.h5");
}

TEST_F(PrecomputeCli, ATwoPointSpaceIsBuiltAsEachPointsLevels) {
  std::ofstream(dir_ / "block.toml") << testing::pair_block_scene();
  ASSERT_EQ(precompute("pair.h5", "--threads 2"), 0) << log();
  EXPECT_NE(log().find("level 1 of 56: the first point, the other free"), std::string::npos) << log();
  EXPECT_NE(log().find("level 3 of 56: the first point, the other held at (7.0, -3.0, 4.0) mm"), std::string::npos)
      << log();
  EXPECT_NE(log().find("level 56 of 56: the second point, the other held at (-7.0, 3.0, 10.0) mm"), std::string::npos)
      << log();
  // A line per level and a total, not each level's full summary.
  EXPECT_NE(log().find("\n  27 points: solved 27, failed 0, unreachable 0, "), std::string::npos) << log();
  EXPECT_NE(log().find("56 levels: 1512 points, 1512 solved, 0 failed or unreachable, "), std::string::npos) << log();
  EXPECT_EQ(log().find("parallel efficiency"), std::string::npos) << log();
  const std::vector<Space> levels = read_space_levels(dir_ / "pair.h5");
  ASSERT_EQ(levels.size(), 56u);
  for (std::size_t k = 0; k < levels.size(); ++k) {
    EXPECT_EQ(levels[k].count(PointStatus::solved), 27u) << "level " << k;
    EXPECT_EQ(levels[k].settings.finger, k == 1 || k >= 29 ? 1 : 0) << "level " << k;
  }
  for (int k = 0; k < 56; ++k) EXPECT_FALSE(fs::exists(dir_ / ("pair.h5.level-" + std::to_string(k) + ".journal")));
  // On-line construction builds spaces of one point.
  EXPECT_EQ(precompute("x.h5", "--online-speed"), 1);
  EXPECT_NE(log().find("has a second point"), std::string::npos) << log();
}

TEST_F(PrecomputeCli, OnLineConstructionRefusesAProbe) {
  std::ofstream(dir_ / "block.toml") << kProbeScene;
  const std::string cmd = "cd '" + dir_.string() + "' && CI=1 '" + TACTUS_BINARY +
                          "' -q precompute block.toml --online-speed >>log.txt 2>&1";
  const int status = std::system(cmd.c_str());
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 1) << log();
  EXPECT_NE(log().find("has a probe"), std::string::npos) << log();
}

TEST_F(PrecomputeCli, SceneWithoutPrecomputeTableIsAnInputError) {
  std::ofstream(dir_ / "block.toml") << "[scene]\nname = \"x\"\n";
  EXPECT_EQ(precompute("space.h5", ""), 1);
  EXPECT_NE(log().find("[precompute]"), std::string::npos);
}

TEST_F(PrecomputeCli, OnlineSpeedSearchRunsAndReportsAFiniteSpeed) {
  auto run = [&](const std::string& args) {
    const std::string cmd = "cd '" + dir_.string() + "' && CI=1 '" + TACTUS_BINARY + "' -q precompute block.toml " +
                            args + " >>log.txt 2>&1";
    const int status = std::system(cmd.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  };
  EXPECT_EQ(run("--threads 1"), 1);  // no -o and no --online-speed
  EXPECT_NE(log().find("-o/--output is required"), std::string::npos) << log();
  ASSERT_EQ(run("--online-speed --online-first 20 --online-dwell 0.1 --threads 2"), 0) << log();
  const std::string out = log();
  EXPECT_NE(out.find("maximum tool speed: "), std::string::npos) << out;
  EXPECT_EQ(out.find("NON-FINITE"), std::string::npos) << out;
}

#ifdef TACTUS_MPIEXEC
/// mpirun of three ranks, stopped after `seconds` (a hang fails the test instead of the suite);
/// the ranks' leak check is off, as below.
std::string three_ranks(int seconds) {
  return "timeout " + std::to_string(seconds) + " env ASAN_OPTIONS=detect_leaks=0:abort_on_error=1 '" +
         TACTUS_MPIEXEC + "' -np 3 --oversubscribe" + (::geteuid() == 0 ? " --allow-run-as-root" : "");
}

TEST_F(PrecomputeCli, ThreeMpiRanksBuildTheSameSpaceAsOneProcess) {
  ASSERT_EQ(precompute("single.h5", "--threads 1"), 0) << log();
  // Open MPI's plugins leave allocations behind at MPI_Finalize and are unloaded, so a
  // sanitizer build's leak check can neither attribute nor suppress them: it is off for the
  // ranks only. Our own code's leaks are checked by the single-process runs of this command.
  const std::string launcher = std::string("ASAN_OPTIONS=detect_leaks=0:abort_on_error=1 '") + TACTUS_MPIEXEC +
                               "' -np 3 --oversubscribe" + (::geteuid() == 0 ? " --allow-run-as-root" : "");
  // One transition owed per rank at a time, and two (the next one queued while it solves).
  for (const std::string in_flight : {"1", "2"}) {
    SCOPED_TRACE("--in-flight " + in_flight);
    const std::string file = "mpi" + in_flight + ".h5";
    ASSERT_EQ(precompute(file, "--in-flight " + in_flight, launcher), 0) << log();
    EXPECT_NE(log().find("MPI"), std::string::npos) << log();
    // CPU time is the ranks' own (getrusage), summed, and efficiency comes from it, not from
    // the solves' wall time, which counts the waits of three ranks on fewer cores.
    const std::string text = log();
    const auto cpu = text.find("CPU-seconds per point (getrusage, summed over every rank)");
    ASSERT_NE(cpu, std::string::npos) << text;
    const auto per = text.rfind(", ", cpu);
    ASSERT_NE(per, std::string::npos);
    EXPECT_GT(std::stod(text.substr(per + 2)), 0.0) << text;
    expect_same(read_space(dir_ / "single.h5"), read_space(dir_ / file));
  }
}

TEST_F(PrecomputeCli, ThreeMpiRanksBuildTheSameProbeSpaceAsOneProcess) {
  std::ofstream(dir_ / "block.toml") << kProbeScene;
  ASSERT_EQ(precompute("single.h5", "--threads 1"), 0) << log();
  const std::string launcher = three_ranks(300);
  ASSERT_EQ(precompute("mpi.h5", "", launcher), 0) << log();
  expect_same_levels(dir_ / "single.h5", dir_ / "mpi.h5");
  // Stopped in the first level: the solver ranks are told there is no next one and end.
  ASSERT_EQ(precompute("part.h5", "--stop-after 5", launcher), 3) << log();
  ASSERT_EQ(precompute("part.h5", "--resume", launcher), 0) << log();
  expect_same_levels(dir_ / "single.h5", dir_ / "part.h5");
}

TEST_F(PrecomputeCli, TwoTasksInFlightPerRankDoNotWaitOnEachOther) {
  // A finer block (405 nodes): its displacements (9.7 kB a task) are too large for MPI to
  // buffer, so a task sent to a rank still solving the one before is taken only when the rank
  // asks for it. A scheduler that waited there would never take the rank's answer while the
  // rank waited for it to be taken.
  std::string scene = kScene;
  scene.replace(scene.find("cells = [4, 4, 2]"), 17, "cells = [8, 8, 4]");
  std::ofstream(dir_ / "block.toml") << scene;
  ASSERT_EQ(precompute("single.h5", "--threads 1"), 0) << log();
  const std::string launcher = three_ranks(120);
  ASSERT_EQ(precompute("mpi.h5", "--in-flight 2", launcher), 0) << log();
  expect_same(read_space(dir_ / "single.h5"), read_space(dir_ / "mpi.h5"));
}

TEST_F(PrecomputeCli, AStalledRanksTaskIsReissuedAndItsLateAnswerIgnored) {
  ASSERT_EQ(precompute("single.h5", "--threads 1"), 0) << log();
  // Rank 1 stalls 8 s before its 3rd task; with a fixed timeout of 2 s (a sanitizer build
  // on a loaded machine takes 0.5 s a solve, so 10 x the median solve would outlast the
  // stall) the task goes to rank 2, and rank 1's answer, when it comes, is ignored.
  const std::string launcher = std::string("TACTUS_PRECOMPUTE_STALL=1:3:8 ") +
                               "ASAN_OPTIONS=detect_leaks=0:abort_on_error=1 '" + TACTUS_MPIEXEC +
                               "' -np 3 --oversubscribe" +
                               (::geteuid() == 0 ? " --allow-run-as-root" : "");
  // With two transitions owed per rank, the task queued behind the stalled one goes too.
  for (const std::string in_flight : {"1", "2"}) {
  SCOPED_TRACE("--in-flight " + in_flight);
  const std::string file = "mpi" + in_flight + ".h5";
  ASSERT_EQ(precompute(file, "--reissue-floor 2 --reissue-factor 0 --in-flight " + in_flight, launcher), 0) << log();
  // At least the stalled task was reissued and its answer ignored (a load spike on the
  // machine may add another), and no rank was left hung.
  // The summary line: "reissued R transitions after a timeout; ignored L late answers; U
  // ranks unresponsive" (parsed by hand: std::regex trips GCC 12's -Wmaybe-uninitialized
  // under the sanitizers).
  const std::string out = log();
  const std::size_t at = out.find("reissued ");
  ASSERT_NE(at, std::string::npos) << out;
  long reissued = -1, ignored = -1, unresponsive = -1;
  ASSERT_EQ(std::sscanf(out.c_str() + at,
                        "reissued %ld transitions after a timeout; ignored %ld late answers; %ld ranks unresponsive",
                        &reissued, &ignored, &unresponsive),
            3)
      << out;
  EXPECT_GE(reissued, 1);
  EXPECT_GE(ignored, 1);
  EXPECT_EQ(unresponsive, 0);
  // Every point once in the journal and the file: the same space as one process builds.
  expect_same(read_space(dir_ / "single.h5"), read_space(dir_ / file));
  }
}
#endif

}  // namespace
}  // namespace tactus::precompute
