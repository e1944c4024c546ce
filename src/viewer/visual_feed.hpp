#pragma once
// The viewer's side of a run: it receives what the runtime hands a VisualSink (surfaces
// through a triple buffer, haptic frames and events as the recorder drains them) and turns
// the newest of it into a FrameView. Nothing here runs on a haptic thread.
#include <atomic>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "haptics/device.hpp"
#include "runtime/session.hpp"
#include "scene/model.hpp"
#include "viewer/frame.hpp"
#include "viewer/surface_colours.hpp"

namespace tactus::viewer {

/// One point of the live plots.
struct PlotSample {
  double t = 0.0;           ///< [s]
  double force = 0.0;       ///< |force sent| [N]
  double compute_us = 0.0;  ///< haptic frame compute time [µs]
};

/// A device's tool as last seen: where the device is, where the contact holds it.
struct ToolView {
  Vec3 device_position = Vec3::Zero();  ///< first contact sphere at the device pose, scene [m]
  Vec3 proxy_position = Vec3::Zero();   ///< the same sphere held on the surface, scene [m]
  Vec3 contact_point = Vec3::Zero();    ///< scene [m]
  Vec3 force = Vec3::Zero();            ///< on the user's hand, scene axes [N]
  double radius = 0.0;                  ///< [m]
  bool touching = false;
  bool seen = false;  ///< a frame of this device has arrived
  std::string name;   ///< the device's
  bool needle = false;
  Vec3 needle_axis = -Vec3::UnitZ();  ///< scene, towards the tip
  double needle_depth = 0.0;          ///< [m] past where it entered at this site
  std::vector<std::string> layers_passed;
  std::size_t layer_count = 0;
};

class VisualFeed final : public runtime::VisualSink {
 public:
  /// `model` must outlive the feed.
  explicit VisualFeed(const scene::Model& model);

  // runtime::VisualSink (the run's recorder thread; the buffer once, before the loops start).
  TripleBuffer<runtime::SurfaceSnapshot>& surface_buffer(const runtime::SurfaceSnapshot& initial) override;
  void frame(const runtime::HapticFrame& frame) override;
  void event(const runtime::LoopEvent& event) override;

  // The viewer's thread.
  /// The newest surfaces, tools, pressure and forces.
  FrameView build();
  [[nodiscard]] std::vector<ToolView> tools() const;
  /// The plots' samples (about 200 per second of run, the last 20 s).
  [[nodiscard]] std::vector<PlotSample> samples() const;
  /// Safety and contact events, newest last (the last 64), as "t  kind  value".
  [[nodiscard]] std::vector<std::string> events() const;
  /// Per body, the impostor level the haptic loop renders it at (−1: none reported).
  [[nodiscard]] std::vector<std::int32_t> levels() const;
  /// Device → scene mapping of a device (for the mouse device).
  [[nodiscard]] const haptics::WorkspaceMap& map(std::size_t device) const { return devices_.at(device).map; }
  /// Pressure shown at the top of the colour scale [Pa].
  [[nodiscard]] double pressure_full_scale() const { return full_scale_; }

 private:
  struct DeviceTool {
    std::string name;
    haptics::WorkspaceMap map;
    Vec3 offset = Vec3::Zero();  ///< first contact sphere, tool frame
    double radius = 0.0;
    std::vector<std::pair<Vec3, double>> extra_spheres;  ///< the others (sphere sets)
    bool needle = false;
    double needle_length = 0.0;
    std::optional<Vec3> needle_axis;       ///< scene; a scripted insertion line fixes it
    std::vector<std::string> layer_names;  ///< the needle's layers, in its algorithm's order
  };
  /// A needle's insertion site as the frames and events tell it (under mutex_); its depth
  /// follows from the newest frame.
  struct NeedleProgress {
    Vec3 entry = Vec3::Zero();  ///< where the tip first touched at this site, scene [m]
    std::vector<std::int32_t> passed;  ///< layers torn at this site, in order
  };
  [[nodiscard]] Vec3 needle_axis(std::size_t device, const runtime::HapticFrame& frame) const;

  const scene::Model& model_;
  std::vector<DeviceTool> devices_;
  double full_scale_ = 2.0e4;
  double extent_ = 0.1;  ///< the bodies' largest side at rest [m]: sets the arrows' scale
  std::vector<RegionColours> regions_;  ///< per body: its regions' colours (empty: one colour)
  std::unique_ptr<TripleBuffer<runtime::SurfaceSnapshot>> surfaces_;
  // The run's thread builds the buffer while a window may already be drawing: the window
  // reads it only once published here (release / acquire).
  std::atomic<TripleBuffer<runtime::SurfaceSnapshot>*> published_surfaces_{nullptr};
  mutable std::mutex mutex_;  // between the recorder's thread and the viewer's, never a haptic thread
  std::vector<std::optional<runtime::HapticFrame>> latest_;
  std::deque<PlotSample> samples_;
  std::deque<std::string> events_;
  std::vector<std::int32_t> levels_;
  std::vector<NeedleProgress> needles_;
};

/// Hertz-like pressure of a contact force spread over a disc of `radius` around `point`:
/// p(r) = 3F / (2πa²) · √(1 − r²/a²) for each vertex within the disc, 0 outside [Pa].
void add_contact_pressure(const std::vector<Vec3>& positions, const Vec3& point, double force, double radius,
                          std::vector<double>& pressure);

}  // namespace tactus::viewer
