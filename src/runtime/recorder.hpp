#pragma once
// The recorder: drains what the loops produced (haptic frames, events, simulation steps)
// out of their rings into the recording file and the run's report. It runs off the haptic
// threads (the main thread in real time, between steps in lockstep) and may allocate.
#include <optional>
#include <string>
#include <vector>

#include "core/spsc_ring.hpp"
#include "runtime/haptic_loop.hpp"
#include "runtime/recording_writer.hpp"
#include "runtime/session.hpp"
#include "runtime/vtk_series.hpp"

namespace tactus::runtime {

/// Moves what the loops produced into the recording and the report.
class Recorder {
 public:
  /// Opens the recording when the options ask for one (InputError if it cannot be created).
  Recorder(const scene::Model& m, const SessionOptions& o, std::vector<DeviceChannels*> devices,
           SpscRing<SimulationStep>& steps, SessionReport& report);

  /// Also writes the run's VTK series: the frames' tools and the simulation's nodes as they
  /// are drained (both outlive the recorder).
  void add_vtk(VtkSeries& series, TripleBuffer<NodeSnapshot>& nodes) {
    vtk_ = &series;
    nodes_ = &nodes;
  }
  /// Drains every ring; returns whether anything was moved.
  bool drain();
  /// Writes out the partly filled chunks (a kill then loses nothing drained so far).
  void flush() {
    if (writer_) writer_->flush();
  }
  /// Drains the rings a last time and closes the recording.
  void close();
  /// Per device (scene order), the newest frame drained so far (a default frame before any):
  /// what a caller stepping the run frame by frame reads back (runtime/stepped_run.hpp).
  [[nodiscard]] const std::vector<HapticFrame>& latest_frames() const { return latest_; }

 private:
  std::vector<DeviceChannels*> devices_;
  SpscRing<SimulationStep>& steps_;
  SessionReport& report_;
  bool keep_;
  // Frames are always whole (pose, force and contact together: a replay needs them).
  bool record_steps_, record_events_;
  std::optional<RecordingWriter> writer_;
  std::optional<PalpationTracker> palpation_;  ///< scenes with nodules
  VisualSink* visual_;
  VtkSeries* vtk_ = nullptr;
  TripleBuffer<NodeSnapshot>* nodes_ = nullptr;
  std::vector<HapticFrame> latest_;
};

}  // namespace tactus::runtime
