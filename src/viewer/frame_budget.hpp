#pragma once
// Keeping the visual frame within its budget (seed 000 §4.2 applied to the picture): the
// objects' graphics impostors share a part of the budget by their measured draw time, and the
// rest goes to filling pixels, whose cost the resolution the scene is drawn at sets. A software
// renderer (Mesa's llvmpipe) shades every pixel on the CPU, so there the resolution is what
// brings a frame within 16 ms.
#include <cstddef>
#include <string_view>
#include <vector>

namespace tactus::viewer {

/// Whether the OpenGL renderer string names a CPU rasterizer (llvmpipe, softpipe, swrast,
/// OpenSWR): no multisampling and single-tap shadows there.
[[nodiscard]] bool is_software_renderer(std::string_view gl_renderer);

/// The scale (of the window's width and height) the scene is drawn at, steered by the frame
/// times so that a frame fits `budget_ms`. A frame's fill cost goes with the pixels, the
/// square of the scale, so the scale moves by the square root of the ratio of budget to time,
/// once per `period` frames (a step needs a few frames to show in the times), with a dead band
/// so it settles instead of flickering between two sizes.
class ResolutionGovernor {
 public:
  struct Settings {
    double budget_ms = 16.0;
    double min_scale = 0.35;  ///< below this the picture is too coarse to aim a finger by
    double target = 0.85;     ///< aim at this share of the budget, leaving room for spikes
    double grow_below = 0.6;  ///< grow only when frames take less than this share
    std::size_t period = 8;   ///< frames between two changes
  };
  ResolutionGovernor() : ResolutionGovernor(Settings{}) {}
  explicit ResolutionGovernor(const Settings& settings);

  /// Records a frame's time [ms]; may change the scale for the next frames.
  void add(double frame_ms);
  [[nodiscard]] double scale() const { return scale_; }
  [[nodiscard]] const Settings& settings() const { return settings_; }

 private:
  Settings settings_;
  double scale_ = 1.0;
  std::vector<double> window_;  ///< the frame times since the last change
};

}  // namespace tactus::viewer
