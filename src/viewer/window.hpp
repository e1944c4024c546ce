#pragma once
// `tactus run SCENE --view`: a GLFW window (OpenGL 3.3 core) that draws a run live with the
// snapshots' renderer, a Dear ImGui panel, and the mouse as the first device. The run goes
// on in its own threads (real-time scheduling); the window only reads what the loops
// publish (VisualFeed) and hands the mouse's position over through a SeqLock, so the
// haptic loop never waits for it.
#include <atomic>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "runtime/session.hpp"
#include "scene/model.hpp"

namespace tactus::viewer {

struct WindowOptions {
  int width = 1280, height = 800;  ///< [screen coordinates]
  /// Close the window (and end the run) after this many seconds of wall clock; 0 = never.
  double seconds = 0.0;
  /// Synthetic input fed through the window's own input handlers (tests; docs/viewer.md).
  std::optional<std::filesystem::path> script;
  /// The mouse drives the first device (unless that device is hardware or replayed).
  bool mouse = true;
  /// The visual loop's rate cap [Hz], so that software GL leaves CPU to the run.
  double max_fps = 60.0;
  /// Scenes the panel's switcher offers (paths); empty = no switcher.
  std::vector<std::string> scenes;
  /// The visual frame's budget [ms]: the scene is drawn at the resolution that keeps frames
  /// within it and the objects' graphics impostors share part of it by measured draw time;
  /// 0 = always the full resolution, impostors within a triangle count.
  double frame_budget_ms = 16.0;
};

/// What the visual loop achieved.
struct WindowReport {
  std::uint64_t frames = 0;
  double seconds = 0.0;         ///< [s] wall clock the window was open
  double rate = 0.0;            ///< [Hz] frames / seconds
  double frame_p50_ms = 0.0;    ///< CPU time to build and draw one frame
  double frame_p99_ms = 0.0;
  double scale_p50 = 1.0, scale_min = 1.0;  ///< of the window's size, the scene drawn at
  int width = 0, height = 0;                ///< the window's [screen coordinates]
  bool software_renderer = false;
  std::string renderer;                     ///< OpenGL's renderer string
  /// Per touchable object, its graphics levels' measured draw times [ms], coarse to fine.
  std::vector<std::pair<std::string, std::vector<double>>> level_draw_ms;
  std::string mouse_device;     ///< the scene device the mouse drove, empty = none
  std::string next_scene;       ///< chosen in the panel's switcher: run it next; empty = none
};

/// Whether the mouse may replace scene device `index`: not hardware, not network, not
/// replayed from a recording.
bool mouse_may_drive(const scene::Model& model, std::size_t index, const runtime::SessionOptions& options);

/// Opens the window, runs the session in its own threads until the window is closed,
/// `stop` becomes true (it is also the run's interrupt: set here when the window closes),
/// options.seconds pass, or the run ends by itself; then closes the window. `options`'
/// visual and device_override are set here. Throws InputError when no window can be
/// opened (no display), and rethrows what the run throws.
runtime::SessionReport run_with_window(const scene::Model& model, runtime::SessionOptions options,
                                       const WindowOptions& window, std::atomic<bool>& stop, WindowReport& report);

/// The scene files (*.toml) in `folder`, sorted; empty when it cannot be read.
std::vector<std::string> scene_files(const std::filesystem::path& folder);

/// One line for the run's report: "visual loop: N frames in S s, R Hz; frame time p50 / p99 ms".
std::string format_window_report(const WindowReport& report);

}  // namespace tactus::viewer
