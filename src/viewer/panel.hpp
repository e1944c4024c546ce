#pragma once
// The window's Dear ImGui panel: live plots of the force and the haptic loop's compute
// time, safety events, display switches, camera and finger controls, the shortcuts.
#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "runtime/live_parameters.hpp"
#include "viewer/frame.hpp"
#include "viewer/touchables_view.hpp"
#include "viewer/visual_feed.hpp"

namespace tactus::viewer {

/// What the panel shows (read-only, gathered by the window each frame).
struct PanelInputs {
  std::string scene;
  std::string mouse_device;  ///< the device the mouse drives; empty = none
  std::string recording;     ///< the run's recording file; empty = none
  double visual_rate = 0.0;  ///< [Hz]
  double frame_ms = 0.0;     ///< CPU time of the last frame [ms]
  double t = 0.0;            ///< [s] simulated time of the surfaces shown
  std::vector<ToolView> tools;  ///< each device's tool
  std::vector<PlotSample> samples;
  std::vector<std::string> events;
  /// The run's live parameters (the panel edits them); null = none.
  runtime::LiveParameters* live = nullptr;
  std::vector<std::string> body_names, device_names;
  bool emergency_stopped = false;
  /// Scenes the switcher offers (paths); empty = no switcher.
  std::vector<std::string> scenes;
  /// The brush of the scene's property images (the panel edits it); null = none to paint.
  PaintBrush* brush = nullptr;
  std::string painted;  ///< what the brush last did, or where the images were saved
};

/// What the user asked for through the panel's buttons.
struct PanelActions {
  bool reset_camera = false;
  bool reset_finger = false;
  bool close = false;
  bool emergency_stop = false;
  std::string switch_to;  ///< a scene chosen in the switcher
  bool save_images = false;  ///< write the painted property images
};

/// Builds the panel in the current ImGui frame; the display switches are edited in place.
PanelActions draw_panel(const PanelInputs& in, ViewOptions& view);

/// `values` reduced to `columns` pairs (each column's least and largest, in time order), so a
/// plot `columns` pixels wide draws every spike with two points a column; unchanged when it
/// has no more than two values a column.
[[nodiscard]] std::vector<float> min_max_envelope(std::span<const float> values, std::size_t columns);

/// The keyboard and mouse shortcuts, as listed in the panel and in docs/viewer.md.
const std::vector<std::pair<const char*, const char*>>& shortcuts();

}  // namespace tactus::viewer
