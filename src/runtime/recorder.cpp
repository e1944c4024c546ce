#include "runtime/recorder.hpp"

#include <algorithm>
#include <chrono>

#include "core/version.hpp"

namespace tactus::runtime {

Recorder::Recorder(const scene::Model& m, const SessionOptions& o, std::vector<DeviceChannels*> devices,
                   SpscRing<SimulationStep>& steps, SessionReport& report)
    : devices_(std::move(devices)), steps_(steps), report_(report), keep_(o.keep_frames),
      record_steps_(m.recording.timings), record_events_(m.recording.events),
      palpation_(PalpationTracker::for_model(m)), visual_(o.visual),
      latest_(m.devices.size()) {
  for (std::size_t i = 0; i < latest_.size(); ++i) latest_[i].device = static_cast<std::uint16_t>(i);
  if (!o.record) return;
  RecordingHeader h;
  h.scene_name = m.name;
  h.scene_source = o.scene_source.empty() ? m.source : o.scene_source;
  h.scene_text = o.scene_text;
  h.mode = o.scheduling == Scheduling::lockstep ? "lockstep" : "realtime";
  h.haptic_rate = m.rates.haptic;
  h.simulation_rate = m.rates.simulation;
  for (const auto& d : m.devices) h.devices.push_back(d.name);
  h.start_unix_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(
                        std::chrono::system_clock::now().time_since_epoch())
                        .count();
  h.tactus_version = kVersion;
  writer_.emplace(*o.record, h);
}

bool Recorder::drain() {
  bool any = false;
  HapticFrame f;
  LoopEvent e;
  for (DeviceChannels* d : devices_) {
    while (d->frames.try_pop(f)) {
      any = true;
      ++report_.recorded_frames;
      if (writer_) writer_->append(f);
      if (keep_) report_.frames.push_back(f);
      if (f.device < latest_.size()) latest_[f.device] = f;
      if (palpation_) palpation_->add(f);
      if (visual_) visual_->frame(f);
      if (vtk_) vtk_->frame(f);
      auto& dev = report_.devices[f.device];
      dev.max_force_sent = std::max(dev.max_force_sent, f.force.norm());
      dev.contact_frames += f.contact;
    }
    while (d->events.try_pop(e)) {
      any = true;
      ++report_.events[std::string(event_kind_name(e.kind))];
      if (e.kind == EventKind::contact_state)
        report_.contact_states.push_back({e.t, e.device, static_cast<std::uint8_t>(e.value)});
      if (e.kind == EventKind::level_cost) report_.level_costs.emplace_back(e.device, e.value);
      if (e.kind == EventKind::level_switch)
        report_.level_switches.push_back({e.t, e.device, e.detail, static_cast<std::uint32_t>(e.value)});
      if (visual_) visual_->event(e);
      // A level switch names its body in the text (the record has no other field for it).
      if (writer_ && record_events_)
        writer_->append(Event{e.t, e.kind, e.device, e.value,
                              e.kind == EventKind::level_switch ? "body " + std::to_string(e.detail) : std::string{}});
    }
  }
  SimulationStep s;
  while (steps_.try_pop(s)) {
    any = true;
    if (writer_ && record_steps_) writer_->append(s);
  }
  // After the frames: the tools shown with the nodes are the newest drained.
  if (vtk_ && nodes_->update()) {
    any = true;
    vtk_->nodes(nodes_->read());
  }
  return any;
}

void Recorder::close() {
  drain();
  if (palpation_) {
    report_.palpation = palpation_->result();
    if (writer_ && record_events_)
      for (const Event& e : feedback_events(*report_.palpation)) writer_->append(e);
  }
  if (vtk_) {
    vtk_->close();
    report_.vtk_frames = vtk_->frames_written();
    report_.vtk_bytes = vtk_->bytes_written();
  }
  if (writer_) {
    writer_->close();
    report_.recording_bytes = writer_->bytes_written();
  }
}

}  // namespace tactus::runtime
