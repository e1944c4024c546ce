#pragma once
// Trainee feedback of a palpation run (a scene with nodules under a sheet): how much of the
// patch the finger covered, when it first touched over each nodule, how hard it pressed and
// whether it pressed harder than the scene's safe force. Fed frame by frame by the recorder.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "haptics/device.hpp"
#include "runtime/recording.hpp"
#include "scene/model.hpp"

namespace tactus::runtime {

struct NoduleFirstContact {
  std::string body;
  std::string nodule;
  std::optional<double> time;  ///< [s] first frame in contact with the finger over it; none: never
};

struct PalpationFeedback {
  /// Fraction of the patch area (the sheets that have nodules) that lay under the finger's
  /// footprint (a disc of its radius under its centre) in some frame in contact.
  double coverage = 0.0;
  std::vector<NoduleFirstContact> nodules;
  std::uint64_t contact_frames = 0;
  double peak_force = 0.0;  ///< [N] largest force sent while in contact
  double mean_force = 0.0;  ///< [N] mean over the frames in contact
  double safe_force = 0.0;  ///< [N] the scene's limit; 0 = none
  std::uint64_t over_limit_frames = 0;
  double over_limit_time = 0.0;             ///< [s] frames above the limit / haptic rate
  std::optional<double> first_over_limit;   ///< [s]
  double end_time = 0.0;                    ///< [s] last frame seen
};

/// Accumulates the feedback from the haptic frames of every device with a sphere tool.
class PalpationTracker {
 public:
  /// None when the scene is not a palpation scene (no body has nodules).
  static std::optional<PalpationTracker> for_model(const scene::Model& model);

  void add(const HapticFrame& frame);
  [[nodiscard]] PalpationFeedback result() const;

 private:
  struct Finger {
    bool tracked = false;
    double radius = 0.0;
    haptics::WorkspaceMap map;
  };
  struct PatchNode {
    Vec2 position;  ///< rest position in the scene's x–y plane
    double area = 0.0;
    bool covered = false;
  };
  struct NoduleSpot {
    Vec2 center;
    double radius = 0.0;
  };

  PalpationTracker() = default;

  std::vector<Finger> fingers_;  ///< per device
  std::vector<PatchNode> patch_;
  double patch_area_ = 0.0;
  std::vector<NoduleSpot> spots_;
  PalpationFeedback feedback_;
  double force_sum_ = 0.0;
  double haptic_period_ = 1e-3;
};

/// The feedback as recording notes (kind note, the value in `value`, what it is in `text`),
/// stamped at the end of the run.
std::vector<Event> feedback_events(const PalpationFeedback& feedback);
/// Lines for the end of `tactus run`.
std::string format_feedback(const PalpationFeedback& feedback);
/// A JSON object (for --json).
std::string feedback_json(const PalpationFeedback& feedback);

}  // namespace tactus::runtime
