#pragma once
// `tactus snapshot`: run a scene in lockstep to a time and render that instant offscreen,
// with the window's look.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "scene/model.hpp"
#include "viewer/camera.hpp"
#include "viewer/frame.hpp"

namespace tactus::viewer {

/// Where the camera looks from; distance 0 frames the whole scene.
struct CameraSpec {
  double azimuth = 30.0;    ///< [deg]
  double elevation = 35.0;  ///< [deg]
  double distance = 0.0;    ///< [m]
};

struct SnapshotOptions {
  double time = 0.0;  ///< [s] of the run to render
  int width = 960;
  int height = 720;
  CameraSpec camera;
  ViewOptions view;
};

struct Snapshot {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;  ///< rows top to bottom
  OrbitCamera camera;             ///< the camera it was rendered with
  FrameView frame;                ///< what it shows
};

/// "AZ,EL[,DIST]" in degrees and metres; InputError naming `flag` when malformed.
CameraSpec parse_camera(const std::string& text, const std::string& flag);
/// "WxH"; InputError naming `flag` when malformed or outside 16..8192.
void parse_size(const std::string& text, const std::string& flag, int& width, int& height);

/// The camera a snapshot of `frame` uses.
OrbitCamera snapshot_camera(const FrameView& frame, const CameraSpec& spec);

/// Runs the scene in lockstep to options.time and renders it offscreen. Throws InputError
/// for options out of range, std::runtime_error when no offscreen context can be made.
Snapshot take_snapshot(const scene::Model& model, const SnapshotOptions& options);
/// Renders a given frame offscreen (tests; the renderer as a function).
Snapshot render_offscreen(const FrameView& frame, const OrbitCamera& camera, const ViewOptions& view, int width,
                          int height);

}  // namespace tactus::viewer
