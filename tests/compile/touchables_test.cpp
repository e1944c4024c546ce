// The touchable objects of a scene: levels and property images built once, painted by the
// scene's strokes, read back from a saved file; a file for another mesh or a surface the
// images cannot see refused with the body and the file.
#include "compile/touchables.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include "compile/device_setup.hpp"
#include "lod/impostor_cache.hpp"
#include "property_images/property_file.hpp"
#include "scene/scene.hpp"

namespace tactus::compile {
namespace {

namespace fs = std::filesystem;
using property_images::Channel;

struct Folder {
  Folder() : dir(fs::temp_directory_path() / ("tactus_touchables_" + std::to_string(::getpid()))) {
    fs::create_directories(dir);
  }
  ~Folder() { fs::remove_all(dir); }
  [[nodiscard]] scene::Model load(const std::string& text) const {
    scene::LoadOptions o;
    o.base_dir = dir;
    return scene::parse_scene(text, (dir / "room.toml").string(), o);
  }
  fs::path dir;
};

std::string ball(const std::string& mesh, const std::string& properties) {
  return R"([bodies.ball]
kind = "rigid"
mesh = )" + mesh + R"(
levels = { coarse_levels = 1, subdivision_levels = 0 }
[bodies.ball.properties]
resolution = 64
)" + properties + R"(
[devices.hand]
type = "scripted"
trajectory = { type = "press", position = [0.0, 0.0, 0.06], depth = 0.005 }
[tools.finger]
type = "sphere"
device = "hand"
radius = 0.003
[algorithms.touch]
type = "proxy"
tool = "finger"
)";
}
const std::string kSphere = R"({ generator = "sphere", radius = 0.05, subdivisions = 3 })";

TEST(Touchables, PaintedImagesAreSavedAndReadBackForTheSameMesh) {
  const Folder f;
  const scene::Model painted = f.load(ball(kSphere, R"(stiffness = 300.0
[[bodies.ball.properties.paint]]
center = [0.0, 0.0, 0.05]
radius = 0.015
stiffness = 900.0)"));
  const Touchables t = load_touchables(painted);
  ASSERT_TRUE(t.any());
  const auto& o = *t.objects.at(0);
  EXPECT_EQ(o.levels->levels.size(), 2u);
  EXPECT_DOUBLE_EQ(o.properties->lookup(Vec3(0, 0, 0.05), Vec3::UnitZ()).properties[Channel::stiffness], 900.0);
  property_images::write_property_images(f.dir / "ball.h5", *o.properties);

  const scene::Model reloaded = f.load(ball(kSphere, "file = \"ball.h5\""));
  const Touchables back = load_touchables(reloaded);
  EXPECT_DOUBLE_EQ(back.objects.at(0)->properties->lookup(Vec3(0, 0, 0.05), Vec3::UnitZ()).properties[Channel::stiffness],
                   900.0);
  // The device's algorithm renders the objects itself; the interaction loop touches nothing.
  const DeviceSetup setup = setup_device(reloaded, 0, {}, &back);
  EXPECT_NE(setup.model.find<haptics::ProxyOnObjects>(), nullptr);
  EXPECT_TRUE(setup.bodies.empty());
  EXPECT_EQ(setup.local_model, contact::LocalModelKind::plane);

  // The same file on another mesh: refused with the file and the reason.
  const scene::Model other = f.load(ball(R"({ generator = "sphere", radius = 0.05, subdivisions = 2 })", "file = \"ball.h5\""));
  try {
    (void)load_touchables(other);
    FAIL() << "a file for another mesh was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("ball.h5"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("body 'ball': made for another mesh"), std::string::npos) << e.what();
  }
}

TEST(Touchables, ALevelFileNamedByTheSceneIsReadOrRefused) {
  const Folder f;
  const auto with_levels = [&](const std::string& subdivisions) {
    return f.load(R"([bodies.ball]
kind = "rigid"
mesh = { generator = "sphere", radius = 0.05, subdivisions = )" + subdivisions + R"( }
levels = { coarse_levels = 1, subdivision_levels = 0, file = "ball.tlod" }
)");
  };
  // Written ahead for the 3-subdivision sphere with these parameters.
  lod::ImpostorParams p;
  p.coarse_levels = 1;
  p.subdivision_levels = 0;
  std::ofstream(f.dir / "ball.tlod") << "placeholder";  // the scene wants the file to exist
  const scene::Model m3 = with_levels("3");
  lod::save_impostor_cache(f.dir / "ball.tlod", lod::build_impostors(m3.bodies[0].surface, p));
  EXPECT_EQ(load_touchables(m3).objects.at(0)->levels->levels.size(), 2u);
  try {
    (void)load_touchables(with_levels("2"));
    FAIL() << "a level file for another mesh was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(e.where().file.find("ball.tlod"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("body 'ball'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("another mesh"), std::string::npos) << e.what();
  }
}

TEST(Touchables, AnOpenSurfaceIsRefusedWithTheBody) {
  const Folder f;
  const scene::Model m = f.load(ball(R"({ generator = "grid_plate", size = [0.1, 0.1], cells = 4 })", "stiffness = 300.0"));
  try {
    (void)load_touchables(m);
    FAIL() << "an open surface was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("body 'ball'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("closed"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace tactus::compile
