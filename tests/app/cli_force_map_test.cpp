// `tactus run --force-map` as a user runs it: a PNG, its legend and the trainee feedback.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace fs = std::filesystem;

namespace {

struct Result {
  int exit_code;
  std::string out;
  std::string err;
};

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

Result run(const fs::path& dir, const std::string& args) {
  const fs::path out = dir / "stdout.txt";
  const fs::path err = dir / "stderr.txt";
  const std::string cmd = std::string("CI=1 '") + TACTUS_BINARY + "' " + args + " >'" + out.string() + "' 2>'" +
                          err.string() + "' </dev/null";
  const int status = std::system(cmd.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(out), slurp(err)};
}

TEST(CliForceMap, NoduleSceneWritesMapAndFeedback) {
  const fs::path dir = fs::temp_directory_path() / "tactus_cli_force_map";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path scene = fs::path(TACTUS_SOURCE_DIR) / "scenes/nodule.toml";
  const fs::path png = dir / "map.png";
  const fs::path json = dir / "run.json";
  // The first lines of the scan are enough to draw the map and give feedback.
  const Result r = run(dir, "run '" + scene.string() + "' --lockstep --duration 2 --force-map '" + png.string() +
                                "' --json '" + json.string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(slurp(png).substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  EXPECT_NE(r.out.find("force map"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("viridis from 0 N"), std::string::npos);
  EXPECT_NE(r.out.find("palpation feedback:"), std::string::npos);
  EXPECT_NE(r.out.find("first contact over nodule skin.soft"), std::string::npos);
  EXPECT_NE(slurp(json).find("\"palpation\": {\"coverage\": "), std::string::npos);

  // A PNG that cannot be written is the user's error: exit 1 and a clear line.
  const Result bad = run(dir, "run '" + scene.string() + "' --lockstep --duration 0.2 --force-map '" +
                                  (dir / "missing" / "map.png").string() + "'");
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.err.find("could not write the PNG file"), std::string::npos) << bad.err;
  fs::remove_all(dir);
}

}  // namespace
