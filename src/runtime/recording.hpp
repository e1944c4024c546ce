#pragma once
// What a recording holds: the scene it ran, every haptic frame, every simulation step and
// the events of a run. The file layout is in docs/recording-format.md.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/math.hpp"

namespace tactus::runtime {

struct RecordingHeader {
  std::string scene_name;
  std::string scene_source;                     ///< the scene file path, or "built-in:default"
  std::string scene_text;                       ///< the whole scene TOML, so a replay needs only the recording
  std::string mode;                             ///< "lockstep" or "realtime"
  double haptic_rate = 0, simulation_rate = 0;  ///< [Hz]
  std::vector<std::string> devices;             ///< device names, index = HapticFrame::device
  std::int64_t start_unix_ns = 0;
  std::string tactus_version;
};

/// Safety flags of a haptic frame (bits of HapticFrame::flags).
enum FrameFlag : std::uint8_t {
  frame_clamped = 1,
  frame_non_finite_replaced = 2,
  frame_ramping = 4,
  frame_fading = 8,
  frame_emergency_stop = 16,
};

struct HapticFrame {
  std::uint64_t frame = 0;  ///< frame index of this device's haptic loop
  double t = 0;             ///< [s] since start (virtual time in lockstep)
  std::uint16_t device = 0;
  std::uint8_t contact = 0;  ///< 0 free, 1 in contact
  std::uint8_t flags = 0;    ///< FrameFlag bits
  std::uint32_t buttons = 0;
  // Initialised: Eigen leaves fixed-size vectors uninitialised, and a frame is written
  // byte for byte.
  Vec3 position = Vec3::Zero();  ///< device pose, device coordinates [m]
  Quat orientation = Quat::Identity();
  Vec3 force = Vec3::Zero();     ///< sent to the device [N], device coordinates
  Vec3 torque = Vec3::Zero();    ///< sent to the device [N·m], device coordinates
  Vec3 proxy = Vec3::Zero();     ///< proxy / contact point, scene coordinates [m]
  std::uint32_t compute_ns = 0;  ///< time spent computing this frame
  std::int32_t late_ns = 0;      ///< start lateness vs its deadline
};

struct SimulationStep {
  std::uint64_t step = 0;
  double t = 0;  ///< [s]
  std::uint32_t compute_ns = 0;
  std::uint32_t solver_iterations = 0;
  std::int32_t late_ns = 0;
};

enum class EventKind : std::uint16_t {
  note,
  contact_begin,
  contact_end,
  force_clamped,
  non_finite_force,
  watchdog_trip,
  device_stall,
  emergency_stop,
  simulation_overrun,
  rupture,
  device_finished,
  contact_state,  ///< a two-finger contact state begins; value 1..9: seed 002 Table I's I..IX
  level_switch,   ///< an object's impostor level changes; value: the new level, detail: its body
  level_cost,     ///< the largest summed cost of the levels in use over the last 100 ms; value [s]
};
/// Number of EventKind values; a stored kind at or above it is malformed.
inline constexpr std::uint16_t event_kind_count = 14;

/// "note", "contact_begin", ...: the names used in CSV ("unknown" out of range).
constexpr std::string_view event_kind_name(EventKind kind) {
  constexpr std::string_view names[event_kind_count] = {
      "note",         "contact_begin",  "contact_end",        "force_clamped", "non_finite_force", "watchdog_trip",
      "device_stall", "emergency_stop", "simulation_overrun", "rupture",       "device_finished",
      "contact_state", "level_switch",   "level_cost"};
  const auto i = static_cast<std::uint16_t>(kind);
  return i < event_kind_count ? names[i] : std::string_view("unknown");
}

struct Event {
  double t = 0;  ///< [s]
  EventKind kind = EventKind::note;
  std::uint16_t device = 0;
  double value = 0;
  std::string text;
};

struct Recording {
  RecordingHeader header;
  std::vector<HapticFrame> frames;
  std::vector<SimulationStep> steps;
  std::vector<Event> events;
  bool complete = false;          ///< the writer closed it cleanly (end chunk present)
  std::string truncation;         ///< empty, or why reading stopped early (with the byte offset)
  std::uint64_t good_chunks = 0;  ///< chunks read and kept, header and end chunk included
};

}  // namespace tactus::runtime
