// tactus.read_recording: a recording file (docs/recording-format.md) as NumPy arrays, views
// over the records the reader built, kept alive by the arrays themselves.
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <filesystem>
#include <memory>

#include "bindings.hpp"
#include "runtime/recording_reader.hpp"

namespace tactus::python {
namespace {

using runtime::Event;
using runtime::HapticFrame;
using runtime::Recording;
using runtime::SimulationStep;

py::dict frames_of(const Recording& r, py::handle owner) {
  static const HapticFrame none{};
  const std::size_t n = r.frames.size();
  const HapticFrame& f = n ? r.frames.front() : none;
  constexpr std::size_t s = sizeof(HapticFrame);
  py::dict out;
  out["t"] = field_view(&f.t, n, s, 0, owner);
  out["device"] = field_view(&f.device, n, s, 0, owner);
  out["frame"] = field_view(&f.frame, n, s, 0, owner);
  out["position"] = field_view(f.position.data(), n, s, 3, owner);
  out["orientation_xyzw"] = field_view(f.orientation.coeffs().data(), n, s, 4, owner);
  out["force"] = field_view(f.force.data(), n, s, 3, owner);
  out["torque"] = field_view(f.torque.data(), n, s, 3, owner);
  out["proxy"] = field_view(f.proxy.data(), n, s, 3, owner);
  out["contact"] = field_view(&f.contact, n, s, 0, owner);
  out["flags"] = field_view(&f.flags, n, s, 0, owner);
  out["buttons"] = field_view(&f.buttons, n, s, 0, owner);
  out["compute_ns"] = field_view(&f.compute_ns, n, s, 0, owner);
  out["late_ns"] = field_view(&f.late_ns, n, s, 0, owner);
  return out;
}

py::dict steps_of(const Recording& r, py::handle owner) {
  static const SimulationStep none{};
  const std::size_t n = r.steps.size();
  const SimulationStep& st = n ? r.steps.front() : none;
  constexpr std::size_t s = sizeof(SimulationStep);
  py::dict out;
  out["t"] = field_view(&st.t, n, s, 0, owner);
  out["step"] = field_view(&st.step, n, s, 0, owner);
  out["compute_ns"] = field_view(&st.compute_ns, n, s, 0, owner);
  out["solver_iterations"] = field_view(&st.solver_iterations, n, s, 0, owner);
  out["late_ns"] = field_view(&st.late_ns, n, s, 0, owner);
  return out;
}

py::dict events_of(const Recording& r, py::handle owner) {
  static const Event none{};
  const std::size_t n = r.events.size();
  const Event& e = n ? r.events.front() : none;
  constexpr std::size_t s = sizeof(Event);
  py::dict out;
  out["t"] = field_view(&e.t, n, s, 0, owner);
  out["kind"] = field_view(reinterpret_cast<const std::uint16_t*>(&e.kind), n, s, 0, owner);
  out["device"] = field_view(&e.device, n, s, 0, owner);
  out["value"] = field_view(&e.value, n, s, 0, owner);
  py::list names, text;
  for (const Event& ev : r.events) {
    names.append(py::str(std::string(runtime::event_kind_name(ev.kind))));
    text.append(py::str(ev.text));
  }
  out["kind_name"] = names;
  out["text"] = text;
  return out;
}

py::dict read_recording(const std::filesystem::path& path) {
  auto rec = std::make_shared<const Recording>(runtime::read_recording(path));
  // The arrays' owner: a capsule holding the recording, released with the last array.
  auto* holder = new std::shared_ptr<const Recording>(rec);
  const py::capsule owner(holder, [](void* p) { delete static_cast<std::shared_ptr<const Recording>*>(p); });
  const runtime::RecordingHeader& h = rec->header;
  py::dict out;
  out["scene_name"] = h.scene_name;
  out["scene_source"] = h.scene_source;
  out["scene_text"] = h.scene_text;
  out["mode"] = h.mode;
  out["haptic_rate"] = h.haptic_rate;
  out["simulation_rate"] = h.simulation_rate;
  out["devices"] = h.devices;
  out["start_unix_ns"] = h.start_unix_ns;
  out["tactus_version"] = h.tactus_version;
  out["complete"] = rec->complete;
  out["truncation"] = rec->truncation;
  out["frames"] = frames_of(*rec, owner);
  out["steps"] = steps_of(*rec, owner);
  out["events"] = events_of(*rec, owner);
  return out;
}

}  // namespace

void bind_recording(py::module_& m) {
  m.def("read_recording", &read_recording, py::arg("path"),
        "Reads a recording (tactus run --record; docs/recording-format.md) into a dict: the header's\n"
        "scene_name, scene_source, scene_text, mode, haptic_rate and simulation_rate [Hz], devices,\n"
        "start_unix_ns, tactus_version; complete and truncation (a file cut short gives what was\n"
        "kept and says where it stopped); and 'frames', 'steps', 'events', each a dict of NumPy\n"
        "arrays with one row per record (frames: t [s], device, frame, position [m],\n"
        "orientation_xyzw, force [N], torque [N m], proxy [m], contact, flags, buttons,\n"
        "compute_ns, late_ns [ns]; steps: t, step, compute_ns, solver_iterations, late_ns;\n"
        "events: t, kind, device, value, and the lists kind_name and text). The arrays are\n"
        "read-only views of the records, not copies; each keeps them alive. Raises\n"
        "tactus.InputError naming the file and byte for a file whose header cannot be read.");
}

}  // namespace tactus::python
