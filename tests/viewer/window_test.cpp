// The window (`tactus run SCENE --view`): a real GLFW window on an Xvfb display, driven by
// a script of synthetic mouse events through the window's own input handlers; plus the
// pieces that need no display (the script parser, the mouse device's hand-over, the
// message when there is no display).
#include <fcntl.h>
#include <gtest/gtest.h>
#include <stb/stb_image.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <utility>
#include <thread>
#include <vector>

#include "core/counting_allocator.hpp"
#include "core/error.hpp"
#include "viewer/mouse_device.hpp"
#include "viewer/overlay.hpp"
#include "viewer/view_script.hpp"

namespace tactus::viewer {
namespace {

namespace fs = std::filesystem;

fs::path scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("tactus_window_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir / name;
}

std::string slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// Runs a shell command, stdout and stderr into `output`; returns the exit status.
int run_command(const std::string& command, std::string& output) {
  const fs::path out = scratch("command_output.txt");
  const int status = std::system((command + " >" + out.string() + " 2>&1").c_str());
  output = slurp(out);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/// An Xvfb server on a display number it picks itself (-displayfd), stopped on destruction.
class Xvfb {
 public:
  Xvfb() {
    const char* candidates[] = {"/usr/bin/Xvfb", "/usr/local/bin/Xvfb"};
    std::string binary;
    for (const char* c : candidates)
      if (::access(c, X_OK) == 0) binary = c;
    if (binary.empty()) {
      why_not_ = "no Xvfb binary (Debian package xvfb; scripts/setup installs it)";
      return;
    }
    int fds[2];
    if (::pipe(fds) != 0) {
      why_not_ = "pipe() failed";
      return;
    }
    pid_ = ::fork();
    if (pid_ == 0) {
      ::close(fds[0]);
      const std::string fd = std::to_string(fds[1]);
      const int devnull = ::open("/dev/null", O_WRONLY);
      if (devnull >= 0) {
        ::dup2(devnull, 1);
        ::dup2(devnull, 2);
      }
      ::execl(binary.c_str(), "Xvfb", "-displayfd", fd.c_str(), "-screen", "0", "1280x1024x24", "-nolisten", "tcp",
              static_cast<char*>(nullptr));
      ::_exit(127);
    }
    ::close(fds[1]);
    // The server writes its display number once it accepts connections.
    std::string number;
    char c = 0;
    while (::read(fds[0], &c, 1) == 1 && c != '\n') number += c;
    ::close(fds[0]);
    if (pid_ < 0 || number.empty()) {
      why_not_ = "Xvfb did not start (no display number reported)";
      return;
    }
    display_ = ":" + number;
  }
  ~Xvfb() {
    if (pid_ > 0) {
      ::kill(pid_, SIGTERM);
      ::waitpid(pid_, nullptr, 0);
    }
  }
  [[nodiscard]] bool ok() const { return !display_.empty(); }
  [[nodiscard]] const std::string& display() const { return display_; }
  [[nodiscard]] const std::string& why_not() const { return why_not_; }

 private:
  pid_t pid_ = -1;
  std::string display_, why_not_;
};

struct FingerLine {
  Vec3 position;
  double force = 0.0;
  bool touching = false;
  double visual_rate = 0.0;
};

// Lines "view: finger at (x, y, z) m, force F N, touching|free; visual R Hz" (sscanf: GCC 12
// warns falsely inside std::regex under the sanitizers).
std::vector<FingerLine> finger_lines(const std::string& output) {
  std::vector<FingerLine> out;
  std::istringstream lines(output);
  std::string line;
  while (std::getline(lines, line)) {
    FingerLine f;
    double x = 0, y = 0, z = 0;
    char state[16] = {};
    if (std::sscanf(line.c_str(), "view: finger at (%lf, %lf, %lf) m, force %lf N, %15[a-z]; visual %lf Hz", &x, &y, &z,
                    &f.force, state, &f.visual_rate) != 6)
      continue;
    f.position = Vec3(x, y, z);
    f.touching = std::string(state) == "touching";
    out.push_back(f);
  }
  return out;
}

/// The rate in "visual loop: N frames in S s, R Hz; ...", or −1 without that line.
double visual_loop_rate(const std::string& output) {
  std::istringstream lines(output);
  std::string line;
  while (std::getline(lines, line)) {
    unsigned long frames = 0;
    double seconds = 0, rate = 0;
    if (std::sscanf(line.c_str(), "visual loop: %lu frames in %lf s, %lf Hz", &frames, &seconds, &rate) == 3) return rate;
  }
  return -1.0;
}

/// The scale of the window the scene was drawn at (p50 and least), from the report's line
/// after the visual loop's; {-1, -1} when there is none.
std::pair<double, double> drawn_scale(const std::string& output) {
  const std::size_t at = output.find("scene drawn at ");
  double p50 = -1.0, least = -1.0;
  int width = 0, height = 0;
  if (at == std::string::npos ||
      std::sscanf(output.c_str() + at, "scene drawn at %lf of %d x %d (p50; least %lf)", &p50, &width, &height,
                  &least) != 4)
    return {-1.0, -1.0};
  return {p50, least};
}

TEST(ViewerScript, ParsesCommandsAndRejectsBadLinesWithTheirLine) {
  const auto c = parse_view_script("# a drag\nwait 0.5\nmove 10 20\npress left shift\nrelease left\nscroll -2 ctrl\n"
                                   "key t\nprint\nscreenshot a.png\nframes 3\nquit\n",
                                   "s.txt");
  ASSERT_EQ(c.size(), 10u);
  EXPECT_EQ(c[0].op, ScriptOp::wait);
  EXPECT_DOUBLE_EQ(c[0].a, 0.5);
  EXPECT_EQ(c[1].op, ScriptOp::move);
  EXPECT_DOUBLE_EQ(c[1].b, 20.0);
  EXPECT_EQ(c[2].op, ScriptOp::press);
  EXPECT_NE(c[2].mods, 0);
  EXPECT_EQ(c[4].op, ScriptOp::scroll);
  EXPECT_DOUBLE_EQ(c[4].a, -2.0);
  EXPECT_EQ(c[7].text, "a.png");
  EXPECT_EQ(c[9].op, ScriptOp::quit);
  const auto live = parse_view_script("surface 500 0.4 0.2\nmaterial 1 3e4\nmaterial 0 2e4 5\nkey space\n", "s.txt");
  ASSERT_EQ(live.size(), 4u);
  EXPECT_EQ(live[0].op, ScriptOp::surface);
  EXPECT_DOUBLE_EQ(live[0].c, 0.2);
  EXPECT_EQ(live[1].op, ScriptOp::material);
  EXPECT_EQ(live[1].button, 1);
  EXPECT_DOUBLE_EQ(live[1].b, -1.0);  // the scene's damping kept
  EXPECT_DOUBLE_EQ(live[2].b, 5.0);
  for (const char* bad : {"jump 1\n", "wait x\n", "press thumb\n", "move 1\n", "frames 1.5\n", "key F1\n",
                          "surface\n", "material 1.5 3e4\n", "material 0\n"}) {
    try {
      parse_view_script(std::string("print\n") + bad, "s.txt");
      ADD_FAILURE() << "accepted: " << bad;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("s.txt:2"), std::string::npos) << e.what();
    }
  }
}

TEST(ViewerMouseDevice, HandsWholePositionsToTheHapticThreadAndKeepsThemInTheWorkspace) {
  haptics::DeviceLimits limits;
  limits.workspace = Aabb{Vec3::Constant(-1.0), Vec3::Constant(1.0)};
  MouseChannel channel(Vec3(0.1, 0.2, 0.3));
  MouseDevice device(channel, limits);
  EXPECT_TRUE(device.read(0.0).position.isApprox(Vec3(0.1, 0.2, 0.3)));
  channel.set(Vec3(5.0, -5.0, 0.5));
  EXPECT_TRUE(device.read(0.0).position.isApprox(Vec3(1.0, -1.0, 0.5)));
  channel.set(Vec3(std::nan(""), 0.0, 0.0));
  EXPECT_TRUE(device.read(0.0).position.allFinite());

  // A writer thread stores (k, 2k, 3k)/1e6 while the reader checks every pose is whole.
  std::atomic<bool> done{false};
  std::thread writer([&] {
    for (int k = 0; k < 200000; ++k) channel.set(Vec3(k, 2.0 * k, 3.0 * k) * 1e-6);
    done.store(true);
  });
  std::uint64_t torn = 0, reads = 0;
  const tactus::testing::AllocationCounter allocations;  // the haptic side of the hand-over allocates nothing
  while (!done.load()) {
    const Vec3 p = device.read(0.0).position;
    torn += (std::abs(p.y() - 2.0 * p.x()) > 1e-12 || std::abs(p.z() - 3.0 * p.x()) > 1e-12) ? 1 : 0;
    ++reads;
  }
  EXPECT_EQ(allocations.count(), 0u);
  writer.join();
  EXPECT_EQ(torn, 0u) << "of " << reads << " reads";
}

TEST(ViewerWindow, FailsClearlyWithoutADisplay) {
  std::string out;
  const int status = run_command("env -u DISPLAY -u WAYLAND_DISPLAY " + std::string(TACTUS_BINARY) + " run " +
                                     TACTUS_SOURCE_DIR + "/scenes/nodule.toml --view --view-seconds 1",
                                 out);
  EXPECT_NE(status, 0) << out;
  EXPECT_NE(out.find("no display"), std::string::npos) << out;
  EXPECT_EQ(out.find("internal error"), std::string::npos) << out;
}

TEST(ViewerWindow, TheMousePalpatesTheNoduleSceneUnderXvfb) {
  Xvfb x;
  if (!x.ok()) GTEST_SKIP() << "no X display can be made here: " << x.why_not();

  const fs::path screenshot = scratch("window.png");
  const fs::path script = scratch("script.txt");
  fs::remove(screenshot);
  {
    std::ofstream s(script);
    // Let the run start, note the finger, drag 120 px to the right, push 8 wheel notches
    // into the skin, note it again, take a screenshot.
    s << "frames 2\nwait 1.0\nprint\n"
         "move 800 450\npress left\nmove 830 450\nmove 860 450\nmove 890 450\nmove 920 450\nrelease left\n"
         "wait 1.0\nprint\n"
         "scroll 8\nwait 1.5\nprint\n"
         "screenshot "
      << screenshot.string() << "\nframes 1\nquit\n";
  }
  std::string out;
  const int status = run_command("DISPLAY=" + x.display() + " " + TACTUS_BINARY + " run " + TACTUS_SOURCE_DIR +
                                     "/scenes/nodule.toml --view --view-seconds 200 --view-script " + script.string(),
                                 out);
  ASSERT_EQ(status, 0) << out;

  const std::vector<FingerLine> lines = finger_lines(out);
  ASSERT_EQ(lines.size(), 3u) << out;
  // The drag moves the finger in the view plane along the camera's right, which is
  // horizontal (the camera orbits about z): z stays, x-y moves. 120 px at the framing
  // camera's depth is about 15 mm (0.09 m of view over 800 px); anything above 5 mm shows
  // the drag went through.
  const Vec3 drag = lines[1].position - lines[0].position;
  EXPECT_GT(drag.head<2>().norm(), 0.005) << out;
  EXPECT_NEAR(drag.z(), 0.0, 1e-4) << out;
  // 8 notches of a third of the finger radius (6 mm) along the view direction, which looks
  // down at the default 35° elevation: Δz = −8 · 2 mm · sin 35° = −9.18 mm. The device
  // reads the mouse's target exactly; 0.1 mm covers the printed digits.
  const Vec3 push = lines[2].position - lines[1].position;
  EXPECT_NEAR(push.z(), -8.0 * 0.002 * std::sin(35.0 * std::numbers::pi / 180.0), 1e-4) << out;
  // Pushed 6 mm past the skin's rest plane, the finger touched and the skin pushed back.
  // The run's device report says so over the whole push (the force at the instant of the
  // print may be faded out by the watchdog where the simulation runs slow, as under ASan).
  EXPECT_FALSE(lines[0].touching) << out;
  const std::size_t report = out.find("finger (mouse): max force sent ");
  ASSERT_NE(report, std::string::npos) << out;
  double max_force = 0.0;
  unsigned long contact_frames = 0;
  ASSERT_EQ(std::sscanf(out.c_str() + report, "finger (mouse): max force sent %lf N, %lu frames in contact", &max_force,
                        &contact_frames),
            2)
      << out;
  EXPECT_GT(contact_frames, 0u) << out;
  // The force needs the simulation to keep pace: where it does not (sanitizer builds), the
  // safety watchdog fades the force out, and that is what the report then says.
  unsigned long watchdog_trips = 0;
  const std::size_t trips = out.find("watchdog trips ", report);
  ASSERT_NE(trips, std::string::npos) << out;
  ASSERT_EQ(std::sscanf(out.c_str() + trips, "watchdog trips %lu", &watchdog_trips), 1) << out;
  if (watchdog_trips == 0) {
    EXPECT_GT(max_force, 0.0) << out;
  }
  // The visual loop reports its rate, live and at the end.
  EXPECT_GT(lines[2].visual_rate, 0.0) << out;
  EXPECT_GT(visual_loop_rate(out), 0.0) << out;
  EXPECT_NE(out.find("the mouse drove 'finger'"), std::string::npos) << out;
  // The frame budget's resolution stays between its least scale and the window's size.
  const auto [scale, least] = drawn_scale(out);
  EXPECT_GE(least, 0.35) << out;
  EXPECT_LE(least, scale) << out;
  EXPECT_LE(scale, 1.0) << out;

  // The screenshot is the window's framebuffer: the scene's skin covers a good part of it
  // and the picture is not one flat colour.
  int width = 0, height = 0, channels = 0;
  unsigned char* pixels = stbi_load(screenshot.string().c_str(), &width, &height, &channels, 3);
  ASSERT_NE(pixels, nullptr) << "no screenshot at " << screenshot << "\n" << out;
  EXPECT_EQ(width, 1280);
  EXPECT_EQ(height, 800);
  std::size_t skin = 0, differing = 0;
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  for (std::size_t i = 0; i < n; ++i) {
    const double r = pixels[3 * i] / 255.0, g = pixels[3 * i + 1] / 255.0, b = pixels[3 * i + 2] / 255.0;
    if (r > 0.35 && r > g + 0.04 && g > b && r - b > 0.12) ++skin;  // warm and light, as snapshot_test
    if (pixels[3 * i] != pixels[0] || pixels[3 * i + 1] != pixels[1] || pixels[3 * i + 2] != pixels[2]) ++differing;
  }
  // The overlay: the pressure colour bar (red at its top, blue at its bottom) and the
  // device's force written at the top right.
  const auto at = [&](int column, int row) -> Vec3 {
    const std::size_t i =
        3 * (static_cast<std::size_t>(row) * static_cast<std::size_t>(width) + static_cast<std::size_t>(column));
    return Vec3(pixels[i], pixels[i + 1], pixels[i + 2]) / 255.0;
  };
  const ColourBarPlace bar = colour_bar_place(width, height);
  const int bar_x = (bar.x0 + bar.x1) / 2;
  EXPECT_LT((at(bar_x, bar.y0) - pressure_colour(1.0)).norm(), 0.05) << at(bar_x, bar.y0).transpose();
  EXPECT_LT((at(bar_x, bar.y1 - 1) - pressure_colour(0.0)).norm(), 0.05) << at(bar_x, bar.y1 - 1).transpose();
  int lit = 0;
  for (int row = 8; row < 32; ++row)
    for (int column = width - 220; column < width - 8; ++column) lit += at(column, row).maxCoeff() > 0.6;  // on dark grey
  EXPECT_GT(lit, 30) << "no force written at the top right";
  stbi_image_free(pixels);
  EXPECT_GT(skin, n / 20) << "skin pixels: " << skin << " of " << n;
  EXPECT_GT(differing, n / 10);
}

// The panel's live controls through the same handlers: a softer coupling while touching,
// the constraint-plane and BVH views, the emergency-stop key.
TEST(ViewerWindow, EditsWhileTouchingShowsDebugViewsAndStopsOnTheKey) {
  Xvfb x;
  if (!x.ok()) GTEST_SKIP() << "no X display can be made here: " << x.why_not();

  const fs::path screenshot = scratch("debug_views.png");
  const fs::path script = scratch("live_script.txt");
  fs::remove(screenshot);
  {
    std::ofstream s(script);
    s << "frames 2\nwait 1.0\nscroll 9\nwait 1.5\nprint\n"
         "surface 20 0 0\nwait 1.0\nprint\n"
         "key p\nkey b\nframes 2\nscreenshot "
      << screenshot.string() << "\nframes 1\nkey e\nwait 0.5\nprint\nquit\n";
  }
  std::string out;
  const int status = run_command("DISPLAY=" + x.display() + " " + TACTUS_BINARY + " run " + TACTUS_SOURCE_DIR +
                                     "/scenes/nodule.toml --view --view-seconds 200 --view-script " + script.string(),
                                 out);
  ASSERT_EQ(status, 0) << out;
  const std::vector<FingerLine> lines = finger_lines(out);
  ASSERT_EQ(lines.size(), 3u) << out;
  EXPECT_NE(out.find("view: edited at t = "), std::string::npos) << out;
  unsigned long watchdog_trips = 0;
  const std::size_t trips = out.find("watchdog trips ");
  ASSERT_NE(trips, std::string::npos) << out;
  ASSERT_EQ(std::sscanf(out.c_str() + trips, "watchdog trips %lu", &watchdog_trips), 1) << out;
  if (watchdog_trips == 0) {
    // The finger's centre is 9 · 2 mm · sin 35° − 9 mm = 1.3 mm under the skin's rest
    // plane: the proxy, on the skin, is at most its 6 mm radius plus that away (a little
    // more on a slope). The scene's 100 N/m coupling gives up to 0.73 N there; the edited
    // 20 N/m at most 20 N/m · 15 mm = 0.3 N, whatever the skin does.
    // (Whether the finger touches at the instant of a print depends on how far the skin has
    // come back under it; the bound holds either way.)
    EXPECT_NEAR((lines[1].position - lines[0].position).norm(), 0.0, 1e-9) << out;
    EXPECT_LT(lines[1].force, 0.3) << out;
  }
  // The emergency stop: no force, said at once and in the run's report, which no longer
  // claims the visual loop was headless.
  EXPECT_EQ(lines[2].force, 0.0) << out;
  EXPECT_NE(out.find("view: emergency stop"), std::string::npos) << out;
  EXPECT_NE(out.find("emergency stops 1"), std::string::npos) << out;
  EXPECT_EQ(out.find("visual loop: not running (headless)"), std::string::npos) << out;
  EXPECT_GT(visual_loop_rate(out), 0.0) << out;

  // The BVH's boxes (unlit magenta lines) and the plane's outline (unlit green) show.
  int width = 0, height = 0, channels = 0;
  unsigned char* pixels = stbi_load(screenshot.string().c_str(), &width, &height, &channels, 3);
  ASSERT_NE(pixels, nullptr) << "no screenshot at " << screenshot << "\n" << out;
  std::size_t magenta = 0, green = 0;
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  for (std::size_t i = 0; i < n; ++i) {
    const int r = pixels[3 * i], g = pixels[3 * i + 1], b = pixels[3 * i + 2];
    if (r > 180 && b > 190 && g < 150) ++magenta;
    if (g > 190 && r < 110 && b < 160) ++green;
  }
  stbi_image_free(pixels);
  EXPECT_GT(magenta, 300u) << "BVH pixels";
  // The plane is drawn while the finger touches in the frame shot, which depends on where
  // the skin has come back to under the soft coupling (and a tripped watchdog, as in
  // sanitizer builds, releases the contact): the screenshot's line says whether it was.
  // The plane's geometry is tested without a window (DebugViews in snapshot_test.cpp).
  std::size_t planes = 0, boxes = 0;
  const std::size_t shot = out.find("constraint planes");
  ASSERT_NE(shot, std::string::npos) << out;
  const std::size_t line = out.rfind("; ", shot);
  ASSERT_NE(line, std::string::npos) << out;
  ASSERT_EQ(std::sscanf(out.c_str() + line, "; %zu constraint planes, %zu BVH boxes", &planes, &boxes), 2) << out;
  EXPECT_GT(boxes, 0u) << out;
  if (planes > 0) {
    EXPECT_GT(green, 20u) << "plane pixels\n" << out;
  }
}

// The scene switcher's choice (the script's `scene`, as the panel's list): the run ends with
// its report and the chosen scene runs in a new window (closed by --view-seconds).
TEST(ViewerWindow, TheSceneSwitcherEndsTheRunAndStartsTheChosenScene) {
  Xvfb x;
  if (!x.ok()) GTEST_SKIP() << "no X display can be made here: " << x.why_not();
  const fs::path script = scratch("switch_script.txt");
  {
    std::ofstream s(script);
    s << "scene " << TACTUS_SOURCE_DIR << "/scenes/default.toml\n";
  }
  std::string out;
  const int status = run_command("DISPLAY=" + x.display() + " " + TACTUS_BINARY + " run " + TACTUS_SOURCE_DIR +
                                     "/scenes/nodule.toml --view --view-seconds 3 --view-script " + script.string(),
                                 out);
  ASSERT_EQ(status, 0) << out;
  const std::size_t first = out.find("run of scene 'nodule'");
  const std::size_t second = out.find("run of scene 'default'");
  ASSERT_NE(first, std::string::npos) << out;
  ASSERT_NE(second, std::string::npos) << out;
  EXPECT_LT(first, second) << out;
}

}  // namespace
}  // namespace tactus::viewer
