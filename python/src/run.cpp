// tactus.run: a whole lockstep run (runtime::run_session) and its result. The frames stay
// in the C++ report; the arrays over them are strided views, kept valid by the result.
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <algorithm>
#include <atomic>
#include <csignal>
#include <optional>

#include <fmt/format.h>

#include "bindings.hpp"
#include "core/error.hpp"
#include "runtime/session.hpp"

namespace tactus::python {

struct RunResult {
  runtime::SessionReport report;
  std::vector<std::string> devices;
  /// Per device: its frames are report.frames[first[d], first[d] + count[d]).
  std::vector<std::size_t> first, count;
};

namespace {

using RunHandle = std::shared_ptr<RunResult>;

std::atomic<bool> g_interrupted{false};
static_assert(std::atomic<bool>::is_always_lock_free, "set from a signal handler");

extern "C" void on_interrupt(int) { g_interrupted.store(true); }

/// While a run holds no GIL, Python cannot run its own SIGINT handler. On the main thread
/// this routes Ctrl-C to the run's interrupt flag (the run ends cleanly, its recording
/// closed) and puts Python's handler back afterwards; interrupted() then says whether it
/// came. Elsewhere (signals reach only the main thread's Python) it does nothing.
class CtrlC {
 public:
  CtrlC() {
    const py::module_ threading = py::module_::import("threading");
    if (!threading.attr("current_thread")().is(threading.attr("main_thread")())) return;
    g_interrupted.store(false);
    struct sigaction action {};
    action.sa_handler = on_interrupt;
    sigemptyset(&action.sa_mask);
    installed_ = sigaction(SIGINT, &action, &previous_) == 0;
  }
  ~CtrlC() {
    if (installed_) sigaction(SIGINT, &previous_, nullptr);
  }
  CtrlC(const CtrlC&) = delete;
  CtrlC& operator=(const CtrlC&) = delete;
  [[nodiscard]] const std::atomic<bool>* flag() const { return installed_ ? &g_interrupted : nullptr; }
  [[nodiscard]] bool interrupted() const { return installed_ && g_interrupted.load(); }

 private:
  struct sigaction previous_ {};
  bool installed_ = false;
};

/// A view of one field of `count` consecutive frames: (count,) for a scalar, (count, cols)
/// for a vector whose doubles are contiguous.
template <class T>
py::array frame_field(const runtime::HapticFrame* frames, std::size_t count, const T* field_of_first,
                      std::size_t cols, py::handle owner) {
  return field_view(frames ? field_of_first : nullptr, frames ? count : 0, sizeof(runtime::HapticFrame), cols, owner);
}

std::size_t device_index(const RunResult& r, const py::object& device) {
  if (py::isinstance<py::str>(device)) {
    const auto name = device.cast<std::string>();
    const auto it = std::find(r.devices.begin(), r.devices.end(), name);
    if (it == r.devices.end()) throw py::key_error("no device '" + name + "' in this run");
    return static_cast<std::size_t>(it - r.devices.begin());
  }
  const auto i = device.cast<std::size_t>();
  if (i >= r.devices.size()) throw py::index_error("device index out of range");
  return i;
}

py::dict frames_of(const py::object& self, const py::object& device) {
  const auto& r = self.cast<const RunResult&>();
  const std::size_t d = device_index(r, device);
  const std::size_t n = r.count[d];
  // A placeholder frame gives the fields' addresses when the device has no frames.
  static const runtime::HapticFrame none{};
  const runtime::HapticFrame* f = n ? &r.report.frames[r.first[d]] : nullptr;
  const runtime::HapticFrame& f0 = n ? *f : none;
  py::dict out;
  out["t"] = frame_field(f, n, &f0.t, 0, self);
  out["frame"] = frame_field(f, n, &f0.frame, 0, self);
  out["position"] = frame_field(f, n, f0.position.data(), 3, self);
  out["orientation_xyzw"] = frame_field(f, n, f0.orientation.coeffs().data(), 4, self);
  out["force"] = frame_field(f, n, f0.force.data(), 3, self);
  out["torque"] = frame_field(f, n, f0.torque.data(), 3, self);
  out["proxy"] = frame_field(f, n, f0.proxy.data(), 3, self);
  out["contact"] = frame_field(f, n, &f0.contact, 0, self);
  out["flags"] = frame_field(f, n, &f0.flags, 0, self);
  out["buttons"] = frame_field(f, n, &f0.buttons, 0, self);
  return out;
}

RunHandle sorted_result(runtime::SessionReport&& report, const scene::Model& model) {
  auto result = std::make_shared<RunResult>();
  result->report = std::move(report);
  // Device by device, each in frame order (the recorder drains device after device, so
  // each device's frames are already in order among themselves).
  auto& frames = result->report.frames;
  std::stable_sort(frames.begin(), frames.end(),
                   [](const runtime::HapticFrame& a, const runtime::HapticFrame& b) { return a.device < b.device; });
  for (std::size_t d = 0; d < model.devices.size(); ++d) {
    result->devices.push_back(model.devices[d].name);
    const auto lo = std::lower_bound(frames.begin(), frames.end(), d,
                                     [](const runtime::HapticFrame& f, std::size_t v) { return f.device < v; });
    const auto hi = std::upper_bound(frames.begin(), frames.end(), d,
                                     [](std::size_t v, const runtime::HapticFrame& f) { return v < f.device; });
    result->first.push_back(static_cast<std::size_t>(lo - frames.begin()));
    result->count.push_back(static_cast<std::size_t>(hi - lo));
  }
  return result;
}

RunHandle run(const ModelHandle& model, double duration, double max_duration,
              const std::optional<std::filesystem::path>& record) {
  runtime::SessionOptions o;
  o.scheduling = runtime::Scheduling::lockstep;
  o.duration = duration;
  o.max_duration = max_duration;
  o.record = record;
  o.scene_text = model->text;
  o.scene_source = model->source;
  o.keep_frames = true;
  runtime::SessionReport report;
  CtrlC ctrl_c;
  o.interrupt = ctrl_c.flag();
  {
    py::gil_scoped_release release;
    report = runtime::run_session(*model, o);
  }
  if (ctrl_c.interrupted()) {
    PyErr_SetString(PyExc_KeyboardInterrupt,
                    fmt::format("run interrupted at t = {:.3f} s{}", report.simulated_time,
                                record ? "; the recording is closed and readable" : "").c_str());
    throw py::error_already_set();
  }
  return sorted_result(std::move(report), *model);
}

py::dict device_report(const runtime::DeviceReport& d) {
  py::dict out;
  out["name"] = d.name;
  out["kind"] = d.kind;
  out["max_force_sent"] = d.max_force_sent;
  out["contact_frames"] = d.contact_frames;
  out["dropped_frames"] = d.dropped_frames;
  out["passivity_frames"] = d.passivity_frames;
  out["passivity_energy"] = d.passivity_energy;
  out["clamped_frames"] = d.safety.clamped;
  return out;
}

}  // namespace

py::object make_run_result(runtime::SessionReport&& report, const scene::Model& model) {
  return py::cast(sorted_result(std::move(report), model));
}

void bind_run(py::module_& m) {
  py::class_<RunResult, RunHandle>(m, "RunResult",
                                   "What a lockstep run produced. The arrays of frames() are read-only views into\n"
                                   "the run's frames, valid as long as any of them (or the result) is alive.")
      .def_readonly("devices", &RunResult::devices, "Device names, in scene order.")
      .def("frames", &frames_of, py::arg("device") = 0,
           "One device's haptic frames (by name or index) in frame order, as a dict of arrays:\n"
           "t (n,) [s], frame (n,) uint64, position (n,3) device coordinates [m],\n"
           "orientation_xyzw (n,4), force (n,3) sent to the device [N, device coordinates],\n"
           "torque (n,3) [N m], proxy (n,3) scene coordinates [m], contact (n,) uint8,\n"
           "flags (n,) uint8, buttons (n,) uint32. Strided views, no copies.")
      .def_property_readonly("simulated_time", [](const RunResult& r) { return r.report.simulated_time; }, "[s]")
      .def_property_readonly("wall_time", [](const RunResult& r) { return r.report.wall_time; }, "[s]")
      .def_property_readonly("recorded_frames", [](const RunResult& r) { return r.report.recorded_frames; })
      .def_property_readonly("recording_bytes", [](const RunResult& r) { return r.report.recording_bytes; })
      .def_property_readonly("dropped_steps", [](const RunResult& r) { return r.report.dropped_steps; })
      .def_property_readonly("events", [](const RunResult& r) { return r.report.events; }, "Count per event kind.")
      .def_property_readonly("device_reports", [](const RunResult& r) {
        py::list out;
        for (const auto& d : r.report.devices) out.append(device_report(d));
        return out;
      }, "Per device: max_force_sent [N], contact_frames, passivity_frames, ... (dicts).");

  m.def("run", &run, py::arg("model"), py::arg("duration") = 0.0, py::arg("max_duration") = 30.0,
        py::arg("record") = std::nullopt,
        "Runs the scene in lockstep (one thread, virtual time: the same forces bit for bit as\n"
        "`tactus run SCENE --lockstep`). duration [s]; 0 = until every device has finished its\n"
        "input, at most max_duration. record: a recording file to write (docs/recording-format.md).\n"
        "The GIL is released during the run; Ctrl-C (on the main thread) ends it cleanly, closes the\n"
        "recording and raises KeyboardInterrupt. Raises tactus.InputError for a scene the runtime\n"
        "cannot run, RuntimeError when the simulation diverges.");
}

}  // namespace tactus::python
