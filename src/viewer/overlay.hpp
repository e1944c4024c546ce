#pragma once
// What is written over the 3D view: each device's force (and a needle's depth and the layers
// it passed) top right, the pressure colour bar with its units, the legend of the bodies'
// colours, the value at each force arrow's tip, and the name of the body under the pointer.
// Laid out once here, painted by the window through Dear ImGui and by snapshots on the CPU
// (core/raster), so both show the same.
#include <optional>
#include <string>
#include <vector>

#include "core/raster.hpp"
#include "viewer/camera.hpp"
#include "viewer/frame.hpp"

namespace tactus::viewer {

struct OverlayRect {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  ///< pixels, x0 ≤ x < x1, y down
  Colour colour = Colour::Zero();
};

struct OverlayText {
  int x = 0, y = 0;  ///< top-left corner, or top-right when right_aligned [px]
  std::string text;
  Colour colour = Colour(0.95, 0.95, 0.95);
  bool right_aligned = false;
};

struct Overlay {
  std::vector<OverlayRect> rects;  ///< painted first
  std::vector<OverlayText> texts;
};

/// Text height of the overlay's labels in snapshots [px].
inline constexpr double kOverlayTextSize = 15.0;
/// The pressure colour bar's place [px], for a width × height view.
struct ColourBarPlace {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};
ColourBarPlace colour_bar_place(int width, int height);

/// The overlay of `frame` seen through `camera` in a width × height view. `hovered`: the
/// pointer's pixel, to name the body under it.
Overlay build_overlay(const FrameView& frame, const OrbitCamera& camera, const ViewOptions& options, int width,
                      int height, const std::optional<std::pair<double, double>>& hovered = std::nullopt);

/// Paints it into an image (snapshots).
void paint(const Overlay& overlay, raster::Image& image);

/// The surface under pixel (x, y): the nearest triangle the camera's ray through it hits;
/// nullopt where the ray meets none.
std::optional<std::size_t> pick_surface(const FrameView& frame, const OrbitCamera& camera, int width, int height,
                                        double x, double y);

}  // namespace tactus::viewer
