// Every bundled scene's recorded forces, kept in tests/data/recordings (how they were made:
// its README.md): `tactus replay` of each must reproduce every force bit for bit, so any
// change that alters a force a user feels is seen here, in the scenes users run.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <regex>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

/// Runs a shell command; its stdout and stderr, and its exit status.
int run(const std::string& command, std::string& out) {
  out.clear();
  FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return -1;
  std::array<char, 4096> buffer{};
  while (std::fgets(buffer.data(), static_cast<int>(buffer.size()), pipe)) out += buffer.data();
  const int status = ::pclose(pipe);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::vector<fs::path> recordings() {
  std::vector<fs::path> out;
  for (const auto& entry : fs::directory_iterator(fs::path(TACTUS_TEST_DATA_DIR) / "recordings"))
    if (entry.path().extension() == ".xz") out.push_back(entry.path());
  std::sort(out.begin(), out.end());
  return out;
}

class Recorded : public ::testing::TestWithParam<std::string> {};

TEST_P(Recorded, ReplaysBitForBit) {
  const fs::path packed = fs::path(TACTUS_TEST_DATA_DIR) / "recordings" / (GetParam() + ".tacrec.xz");
  const fs::path file = fs::temp_directory_path() / ("tactus_replay_regression_" + GetParam() + ".tacrec");
  std::string out;
  ASSERT_EQ(run("xz -dc '" + packed.string() + "' > '" + file.string() + "'", out), 0) << out;
  // BLAS pinned to one thread and one kernel family, as when recorded: CHOLMOD's supernodal
  // factorization (the liver) sums in another order with more threads or other kernels.
  const int status = run("OPENBLAS_NUM_THREADS=1 OPENBLAS_CORETYPE=Haswell " + std::string(TACTUS_BINARY) +
                             " replay '" + file.string() + "' --scene-dir '" + TACTUS_SOURCE_DIR + "/scenes'",
                         out);
  fs::remove(file);
  ASSERT_EQ(status, 0) << out;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(out, m, std::regex(R"((\d+) of (\d+) frames compared, (\d+) forces identical)"))) << out;
  EXPECT_EQ(m[1], m[2]) << "every recorded frame is replayed\n" << out;
  EXPECT_EQ(m[3], m[2]) << "a force differs from the recording: if the change was meant, record the scene again "
                           "(tests/data/recordings/README.md)\n"
                        << out;
  EXPECT_GT(std::stoul(m[2].str()), 250u) << "at least a quarter second of frames\n" << out;
}

std::vector<std::string> names() {
  std::vector<std::string> out;
  for (const fs::path& p : recordings()) out.push_back(p.stem().stem().string());
  return out;
}

INSTANTIATE_TEST_SUITE_P(BundledScenes, Recorded, ::testing::ValuesIn(names()),
                         [](const ::testing::TestParamInfo<std::string>& param) { return param.param; });

// The set is complete: a recording for every bundled scene with a device, but for the one
// that needs a precomputed space to run (liver_cspace: its space takes minutes to build).
TEST(RecordedSet, HoldsEveryBundledSceneWithADevice) {
  const std::vector<std::string> have = names();
  for (const auto& entry : fs::directory_iterator(fs::path(TACTUS_SOURCE_DIR) / "scenes")) {
    if (entry.path().extension() != ".toml") continue;
    const std::string name = entry.path().stem().string();
    // cantilever has no device; liver_cspace, liver_probe and liver_pair are meant to be run
    // from a built space (minutes, and seconds: probe_scene_test.cpp and pair_scene_test.cpp
    // build the last two's and run them).
    if (name == "cantilever" || name == "liver_cspace" || name == "liver_probe" || name == "liver_pair") continue;
    EXPECT_NE(std::find(have.begin(), have.end(), name), have.end()) << "no recording of " << name;
  }
}

}  // namespace
