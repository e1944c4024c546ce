// `--vtk`: a lockstep run's series holds a frame per 1 / rate of simulated time, each body's
// nodes where the run had them at that step, and a folder that cannot be written fails
// before the run. (python/tests/test_outputs.py reads the files with VTK's own reader.)
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

#include "core/error.hpp"
#include "mesh/io/mesh_io.hpp"
#include "runtime/session.hpp"
#include "runtime/stepped_run.hpp"
#include "scene/scene.hpp"

namespace tactus::runtime {
namespace {

namespace fs = std::filesystem;

fs::path scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("tactus_vtk_" + std::to_string(::getpid()) + "_" + name);
  fs::remove_all(dir);
  return dir;
}

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(VtkSeries, ALockstepRunWritesAFramePerPeriodWithTheRunsNodes) {
  const scene::Model m = scene::default_scene();
  const fs::path dir = scratch("run");
  SessionOptions o;
  o.scheduling = Scheduling::lockstep;
  o.duration = 0.2;
  o.vtk = dir;
  o.vtk_rate = 30.0;
  const SessionReport report = run_session(m, o);
  // Frames at 0, 1/30, ..., 6/30 s: seven, each listing the body and the device.
  EXPECT_EQ(report.vtk_frames, 7u);
  const std::string pvd = read_text(dir / (m.name + ".pvd"));
  const std::regex entry("<DataSet timestep=\"([^\"]+)\" part=\"[0-9]+\" name=\"([^\"]+)\" file=\"([^\"]+)\"/>");
  std::size_t entries = 0;
  double last = -1.0;
  std::string last_body_file;
  for (auto it = std::sregex_iterator(pvd.begin(), pvd.end(), entry); it != std::sregex_iterator(); ++it) {
    ++entries;
    EXPECT_TRUE(fs::exists(dir / (*it)[3].str())) << (*it)[3];
    if ((*it)[2] == m.bodies[0].name) {
      EXPECT_GT(std::stod((*it)[1]), last);
      last = std::stod((*it)[1]);
      last_body_file = (*it)[3];
    }
  }
  EXPECT_EQ(entries, 7u * (m.bodies.size() + m.devices.size()));
  const double period = 1.0 / m.rates.simulation;
  EXPECT_GE(last, 6.0 / 30.0 - 1e-12);
  EXPECT_LT(last, 6.0 / 30.0 + period);

  // The nodes the run had after the simulation step at that time: a stepped run to the
  // haptic period of that step, read back through the project's own VTU reader (its
  // doubles are written in full, so they compare exactly).
  SteppedRun stepped(m, SessionOptions{});
  const auto periods = static_cast<std::uint64_t>(std::llround(last * m.rates.haptic)) + 1;
  while (stepped.frames() < periods) stepped.step();
  const VecX& x = *stepped.positions(0);
  const mesh::MeshFile file = mesh::read_mesh(dir / last_body_file);
  ASSERT_TRUE(file.volume);
  ASSERT_EQ(file.volume->vertices.size(), m.bodies[0].volume->vertices.size());
  double moved = 0.0;
  for (std::size_t i = 0; i < file.volume->vertices.size(); ++i) {
    ASSERT_EQ(file.volume->vertices[i], Vec3(x.segment<3>(3 * static_cast<Eigen::Index>(i)))) << i;
    moved = std::max(moved, (file.volume->vertices[i] - m.bodies[0].volume->vertices[i]).norm());
  }
  EXPECT_GT(moved, 1e-5);  // the hand has pressed by then: not the rest mesh
  EXPECT_EQ(file.volume->tets, m.bodies[0].volume->tets);
  fs::remove_all(dir);
}

TEST(VtkSeries, AFolderThatCannotBeWrittenFailsBeforeTheRun) {
  const fs::path blocker = scratch("blocker");
  std::ofstream(blocker) << "a file, not a folder";
  SessionOptions o;
  o.scheduling = Scheduling::lockstep;
  o.duration = 0.1;
  o.vtk = blocker / "series";
  try {
    (void)run_session(scene::default_scene(), o);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().file, (blocker / "series").string());
    EXPECT_NE(e.reason().find("cannot create the folder"), std::string::npos) << e.what();
  }
  fs::remove(blocker);
}

}  // namespace
}  // namespace tactus::runtime
