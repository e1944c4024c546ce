#include "runtime/recording_hdf5.hpp"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/hdf5_file.hpp"

namespace tactus::runtime {
namespace {

using hdf5::Handle;

/// One dataset of one field per record, with its unit (and meaning) as attributes.
class Tables {
 public:
  Tables(hdf5::Writer& w, hid_t group) : w_(w), group_(group) {}

  template <class T>
  void column(const char* name, hid_t type, const std::vector<T>& values, const char* unit, const char* meaning) {
    w_.dataset(group_, name, type, {values.size()}, values.data());
    annotate(name, unit, meaning);
  }
  /// n × k doubles, row-major.
  void rows(const char* name, const std::vector<double>& values, hsize_t k, const char* unit, const char* meaning) {
    w_.dataset(group_, name, H5T_IEEE_F64LE, {values.size() / k, k}, values.data());
    annotate(name, unit, meaning);
  }
  void text(const char* name, const std::vector<std::string>& values, const char* meaning) {
    w_.strings(group_, name, values);
    annotate(name, "", meaning);
  }

 private:
  void annotate(const char* name, const char* unit, const char* meaning) {
    Handle set(H5Dopen2(group_, name, H5P_DEFAULT), H5Dclose);
    w_.check(set.valid(), name);
    w_.attribute(set, "units", std::string(unit));
    w_.attribute(set, "description", std::string(meaning));
  }
  hdf5::Writer& w_;
  hid_t group_;
};

/// A new group (the caller wraps and checks it).
hid_t group(hid_t file, const char* name) { return H5Gcreate2(file, name, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT); }

void append(std::vector<double>& out, const Vec3& v) { out.insert(out.end(), {v.x(), v.y(), v.z()}); }

void write_frames(hdf5::Writer& w, hid_t file, const Recording& r) {
  const Handle g(group(file, "frames"), H5Gclose);
  w.check(g.valid(), "frames");
  std::vector<double> t, position, orientation, force, torque, proxy;
  std::vector<std::uint64_t> frame;
  std::vector<std::uint16_t> device;
  std::vector<std::uint8_t> contact, flags;
  std::vector<std::uint32_t> buttons, compute;
  std::vector<std::int32_t> late;
  for (const HapticFrame& f : r.frames) {
    t.push_back(f.t);
    frame.push_back(f.frame);
    device.push_back(f.device);
    contact.push_back(f.contact);
    flags.push_back(f.flags);
    buttons.push_back(f.buttons);
    append(position, f.position);
    orientation.insert(orientation.end(), {f.orientation.w(), f.orientation.x(), f.orientation.y(), f.orientation.z()});
    append(force, f.force);
    append(torque, f.torque);
    append(proxy, f.proxy);
    compute.push_back(f.compute_ns);
    late.push_back(f.late_ns);
  }
  Tables tab(w, g);
  tab.column("t", H5T_IEEE_F64LE, t, "s", "time since the start (virtual time in lockstep)");
  tab.column("device", H5T_STD_U16LE, device, "", "device index into /devices");
  tab.column("frame", H5T_STD_U64LE, frame, "", "frame index of the device's haptic loop");
  tab.rows("position", position, 3, "m", "device position x, y, z, device coordinates");
  tab.rows("orientation", orientation, 4, "", "device orientation quaternion w, x, y, z");
  tab.column("buttons", H5T_STD_U32LE, buttons, "", "button bits");
  tab.rows("force", force, 3, "N", "force sent to the device, device coordinates");
  tab.rows("torque", torque, 3, "N m", "torque sent to the device, device coordinates");
  tab.column("contact", H5T_STD_U8LE, contact, "", "0 free, 1 in contact");
  tab.column("flags", H5T_STD_U8LE, flags, "",
             "safety flags: 1 clamped, 2 non-finite force replaced, 4 ramping, 8 fading, 16 emergency stop");
  tab.rows("proxy", proxy, 3, "m", "proxy / contact point, scene coordinates");
  tab.column("compute_ns", H5T_STD_U32LE, compute, "ns", "compute time of the frame");
  tab.column("late_ns", H5T_STD_I32LE, late, "ns", "lateness of the frame's start against its deadline");
}

void write_steps(hdf5::Writer& w, hid_t file, const Recording& r) {
  const Handle g(group(file, "steps"), H5Gclose);
  w.check(g.valid(), "steps");
  std::vector<std::uint64_t> step;
  std::vector<double> t;
  std::vector<std::uint32_t> compute, iterations;
  std::vector<std::int32_t> late;
  for (const SimulationStep& s : r.steps) {
    step.push_back(s.step);
    t.push_back(s.t);
    compute.push_back(s.compute_ns);
    iterations.push_back(s.solver_iterations);
    late.push_back(s.late_ns);
  }
  Tables tab(w, g);
  tab.column("t", H5T_IEEE_F64LE, t, "s", "time reached by the step");
  tab.column("step", H5T_STD_U64LE, step, "", "simulation step index");
  tab.column("compute_ns", H5T_STD_U32LE, compute, "ns", "compute time of the step");
  tab.column("solver_iterations", H5T_STD_U32LE, iterations, "", "linear solver iterations");
  tab.column("late_ns", H5T_STD_I32LE, late, "ns", "lateness of the step's start against its deadline");
}

void write_events(hdf5::Writer& w, hid_t file, const Recording& r) {
  const Handle g(group(file, "events"), H5Gclose);
  w.check(g.valid(), "events");
  std::vector<double> t, value;
  std::vector<std::uint16_t> kind, device;
  std::vector<std::string> names, text;
  for (const Event& e : r.events) {
    t.push_back(e.t);
    kind.push_back(static_cast<std::uint16_t>(e.kind));
    names.emplace_back(event_kind_name(e.kind));
    device.push_back(e.device);
    value.push_back(e.value);
    text.push_back(e.text);
  }
  Tables tab(w, g);
  tab.column("t", H5T_IEEE_F64LE, t, "s", "time of the event");
  tab.column("kind", H5T_STD_U16LE, kind, "", "event kind number (docs/recording-format.md)");
  tab.text("kind_name", names, "event kind name, as in the CSV export");
  tab.column("device", H5T_STD_U16LE, device, "", "device index into /devices");
  tab.column("value", H5T_IEEE_F64LE, value, "", "the event's number (its unit depends on the kind)");
  tab.text("text", text, "the event's text");
}

}  // namespace

void write_recording_hdf5(const Recording& r, const std::filesystem::path& path) {
  const hdf5::QuietErrors quiet;
  Handle file(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose);
  if (!file.valid()) hdf5::fail(path, "cannot create the file");
  hdf5::Writer w(path, "the recording's HDF5 export");
  const RecordingHeader& h = r.header;
  w.attribute(file, "format", std::string("tactus recording export 1"));
  w.attribute(file, "scene_name", h.scene_name);
  w.attribute(file, "scene_source", h.scene_source);
  w.attribute(file, "mode", h.mode);
  w.attribute(file, "tactus_version", h.tactus_version);
  w.attribute(file, "haptic_rate", H5T_IEEE_F64LE, &h.haptic_rate);
  w.attribute(file, "simulation_rate", H5T_IEEE_F64LE, &h.simulation_rate);
  w.attribute(file, "start_unix_ns", H5T_STD_I64LE, &h.start_unix_ns);
  const std::uint8_t complete = r.complete ? 1 : 0;
  w.attribute(file, "complete", H5T_STD_U8LE, &complete);
  w.attribute(file, "truncation", r.truncation);
  w.strings(file, "scene_text", {h.scene_text});
  w.strings(file, "devices", h.devices);
  write_frames(w, file, r);
  write_steps(w, file, r);
  write_events(w, file, r);
  if (H5Fflush(file, H5F_SCOPE_GLOBAL) < 0) hdf5::fail(path, "could not write the file");
}

}  // namespace tactus::runtime
