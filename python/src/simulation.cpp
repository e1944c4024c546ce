// tactus.Simulation: a lockstep run stepped frame by frame from Python
// (runtime/stepped_run.hpp), with devices whose pose Python sets. The newest frame of each
// device lives in the run's recorder, at a fixed place that every step overwrites: the
// arrays over it are live views, not copies.
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <algorithm>
#include <array>
#include <map>
#include <optional>

#include "bindings.hpp"
#include "haptics/force_algorithm.hpp"
#include "haptics/haptic_step.hpp"
#include "runtime/live_parameters.hpp"
#include "runtime/stepped_run.hpp"

namespace tactus::python {
namespace {

/// The first error a Python force algorithm raised, kept until step() raises it.
struct CallbackError {
  std::optional<py::error_already_set> error;
};

/// A force written in Python, as an overlay of a device's haptic loop: every frame it calls
/// fn(t, position, velocity, contact_force, touching) and adds the 3 values it returns (force
/// on the hand, scene coordinates [N]) to the contact's force, before the safety layer (which
/// clamps it and stops a NaN as it stops any algorithm's). The haptic step calls render()
/// with the GIL released (step() releases it); this takes it back for the call. A lockstep
/// run's one thread is the only caller, so a Python call in the haptic loop is possible
/// there and nowhere else: it is not real-time code.
class PythonOverlay final : public haptics::ForceAlgorithm {
 public:
  PythonOverlay(py::function fn, std::shared_ptr<CallbackError> error) : fn_(std::move(fn)), error_(std::move(error)) {}
  ~PythonOverlay() override {
    py::gil_scoped_acquire gil;  // the run may be torn down where the GIL is released
    fn_ = py::function();
  }
  PythonOverlay(const PythonOverlay&) = delete;
  PythonOverlay& operator=(const PythonOverlay&) = delete;

  [[nodiscard]] Stage stage() const override { return Stage::overlay; }
  [[nodiscard]] std::unique_ptr<haptics::AlgorithmState> make_state() const override {
    return std::make_unique<haptics::AlgorithmState>();
  }
  [[nodiscard]] haptics::Rendering render(const haptics::FrameInputs& f, haptics::AlgorithmState&) const override {
    haptics::Rendering r;
    r.surface_time = f.t;  // it renders nothing the simulation publishes
    py::gil_scoped_acquire gil;
    if (error_->error) return r;  // after an error, nothing more until step() raises it
    try {
      auto triple = [](const Vec3& v) { return py::make_tuple(v.x(), v.y(), v.z()); };
      const py::object out = fn_(f.t, triple(f.position), triple(f.velocity), triple(f.contact_force), f.contact_touching);
      const auto force = out.cast<std::array<double, 3>>();
      r.force = Vec3(force[0], force[1], force[2]);
    } catch (py::error_already_set& e) {
      error_->error = std::move(e);
    } catch (const py::cast_error&) {
      PyErr_SetString(PyExc_TypeError, "a force algorithm must return 3 numbers: the force on the hand [N]");
      error_->error = py::error_already_set();
    }
    return r;
  }

 private:
  py::function fn_;
  std::shared_ptr<CallbackError> error_;
};

struct Simulation {
  ModelHandle model;  // the run reads the model for its whole life
  std::unique_ptr<runtime::LiveParameters> live;  // edits the run reads at its steps
  std::shared_ptr<CallbackError> callback_error = std::make_shared<CallbackError>();
  std::unique_ptr<runtime::SteppedRun> run;
};

std::size_t index_of(const std::vector<std::string>& names, const py::object& item, const char* what) {
  if (py::isinstance<py::str>(item)) {
    const auto name = item.cast<std::string>();
    for (std::size_t i = 0; i < names.size(); ++i)
      if (names[i] == name) return i;
    throw py::key_error(std::string("no ") + what + " '" + name + "'");
  }
  const auto i = item.cast<std::size_t>();
  if (i >= names.size()) throw py::index_error(std::string(what) + " index out of range");
  return i;
}

std::vector<std::string> device_names(const scene::Model& m) {
  std::vector<std::string> out;
  for (const auto& d : m.devices) out.push_back(d.name);
  return out;
}

std::vector<std::string> body_names(const scene::Model& m) {
  std::vector<std::string> out;
  for (const auto& b : m.bodies) out.push_back(b.name);
  return out;
}

/// A live (devices,) or (devices, cols) view of one field of the newest frames.
template <class T>
py::array latest_field(const py::object& self, const T* (*field)(const runtime::HapticFrame&), std::size_t cols) {
  const auto& frames = self.cast<const Simulation&>().run->latest_frames();
  std::vector<std::size_t> shape{frames.size()}, strides{sizeof(runtime::HapticFrame)};
  if (cols > 0) {
    shape.push_back(cols);
    strides.push_back(sizeof(T));
  }
  py::array a(py::dtype::of<T>(), shape, strides, frames.empty() ? nullptr : field(frames.front()), self);
  py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return a;
}

std::unique_ptr<Simulation> make(const ModelHandle& model, const std::vector<std::string>& controlled,
                                 const std::optional<std::filesystem::path>& record, bool keep_frames,
                                 const std::map<std::string, py::function>& force_algorithms) {
  runtime::SessionOptions o;
  o.scheduling = runtime::Scheduling::lockstep;
  o.record = record;
  o.scene_text = model->text;
  o.scene_source = model->source;
  o.keep_frames = keep_frames;
  auto sim = std::make_unique<Simulation>();
  sim->model = model;
  sim->live = std::make_unique<runtime::LiveParameters>(*model);
  o.live = sim->live.get();
  const std::vector<std::string> devices = device_names(*model);
  for (const auto& [name, fn] : force_algorithms)
    if (std::find(devices.begin(), devices.end(), name) == devices.end())
      throw py::key_error("force_algorithms: no device '" + name + "'");
  std::map<std::string, std::shared_ptr<const haptics::ForceAlgorithm>> overlays;
  for (const auto& [name, fn] : force_algorithms)
    overlays[name] = std::make_shared<PythonOverlay>(fn, sim->callback_error);
  o.customize_haptics = [overlays](const scene::Model& m, std::size_t device, haptics::HapticModel& haptic) {
    if (const auto it = overlays.find(m.devices[device].name); it != overlays.end()) haptic.algorithms.push_back(it->second);
  };
  py::gil_scoped_release release;  // building the loops compiles the bodies
  sim->run = std::make_unique<runtime::SteppedRun>(*model, std::move(o), controlled);
  return sim;
}

}  // namespace

void bind_simulation(py::module_& m) {
  py::class_<Simulation>(m, "Simulation",
                         "A lockstep run of a scene stepped frame by frame from Python.\n\n"
                         "Each step() is one haptic period of every device (the simulation and interaction\n"
                         "steps due run first), exactly as `tactus run --lockstep` schedules them: stepping\n"
                         "a scene to a time gives the same forces bit for bit. Devices named in `controlled`\n"
                         "read the pose set by set_device_pose() instead of their scene entry.\n\n"
                         "forces, device_positions, proxies and contacts are live read-only views of the\n"
                         "newest frame of each device: every step() overwrites them in place (copy to keep\n"
                         "a value); they keep the Simulation alive. body_positions() returns a copy.")
      .def(py::init(&make), py::arg("model"), py::arg("controlled") = std::vector<std::string>{},
           py::arg("record") = std::nullopt, py::arg("keep_frames") = false,
           py::arg("force_algorithms") = std::map<std::string, py::function>{},
           "controlled: names of devices whose pose Python sets (a device written in Python: pose it\n"
           "before each step); record: a recording file to write; keep_frames: keep every frame for the\n"
           "RunResult finish() returns (memory grows with the run); force_algorithms: device name ->\n"
           "fn(t, position, velocity, contact_force, touching) returning the force (3 numbers, scene\n"
           "coordinates [N]) added to that device's contact force every haptic frame, as an overlay of its\n"
           "haptic loop (positions of the tool [m], velocity [m/s], the contact's force after smoothing\n"
           "[N], all scene coordinates). An exception it raises stops step() and is raised from it.")
      .def("step", [](Simulation& s, std::uint64_t frames) {
        // In slices of 1,000 periods (about a second of scene time at 1 kHz), between which
        // Python's pending signals run: Ctrl-C raises KeyboardInterrupt after the slice.
        constexpr std::uint64_t kSlice = 1000;
        for (std::uint64_t done = 0; done < frames;) {
          const std::uint64_t slice = std::min(kSlice, frames - done);
          {
            py::gil_scoped_release release;
            for (std::uint64_t i = 0; i < slice && !s.callback_error->error; ++i) s.run->step();
          }
          if (s.callback_error->error) {
            // A force algorithm raised: its exception, here (the frame went on without it).
            py::error_already_set e = std::move(*s.callback_error->error);
            s.callback_error->error.reset();
            throw e;
          }
          done += slice;
          if (done < frames && PyErr_CheckSignals() != 0) throw py::error_already_set();
        }
      }, py::arg("frames") = 1,
         "Advances `frames` haptic periods (the GIL is released meanwhile). Ctrl-C stops it after\n"
         "the current slice of 1,000 periods with KeyboardInterrupt; the periods stepped stay and\n"
         "the Simulation can go on.")
      .def_property_readonly("frame", [](const Simulation& s) { return s.run->frames(); },
                             "Haptic periods stepped so far; the next runs at frame / haptic rate.")
      .def_property_readonly("time", [](const Simulation& s) { return s.run->time(); },
                             "Time of the last period stepped [s] (0 before the first).")
      .def_property_readonly("model", [](const Simulation& s) { return s.model; })
      .def_property_readonly("devices", [](const Simulation& s) { return device_names(*s.model); })
      .def("is_controlled", [](const Simulation& s, const py::object& device) {
        return s.run->controlled(index_of(device_names(*s.model), device, "device"));
      }, py::arg("device"))
      .def("set_device_pose", [](Simulation& s, const py::object& device, const std::array<double, 3>& position,
                                 const std::optional<std::array<double, 4>>& orientation_wxyz, std::uint32_t buttons) {
        haptics::DevicePose pose;
        pose.position = Vec3(position[0], position[1], position[2]);
        if (orientation_wxyz) {
          const auto& q = *orientation_wxyz;
          pose.orientation = Quat(q[0], q[1], q[2], q[3]);  // as given: a replay stays bit for bit
        }
        pose.buttons = buttons;
        const std::size_t d = index_of(device_names(*s.model), device, "device");
        if (!s.run->controlled(d)) throw py::value_error("device '" + s.model->devices[d].name + "' is not controlled");
        s.run->set_pose(d, pose);
      }, py::arg("device"), py::arg("position"), py::arg("orientation_wxyz") = std::nullopt, py::arg("buttons") = 0,
         "The pose a controlled device reads from the next step on, in device coordinates [m]\n"
         "(the scene's device entry maps them to the scene: scale, rotation, offset); the orientation\n"
         "is a unit quaternion (w, x, y, z), used as given.")
      .def_property_readonly("forces", [](py::object self) {
        return latest_field<double>(self, [](const runtime::HapticFrame& f) { return f.force.data(); }, 3);
      }, "(devices, 3) force sent in each device's newest frame [N, device coordinates]; live view.")
      .def_property_readonly("device_positions", [](py::object self) {
        return latest_field<double>(self, [](const runtime::HapticFrame& f) { return f.position.data(); }, 3);
      }, "(devices, 3) device positions of the newest frames [m, device coordinates]; live view.")
      .def_property_readonly("proxies", [](py::object self) {
        return latest_field<double>(self, [](const runtime::HapticFrame& f) { return f.proxy.data(); }, 3);
      }, "(devices, 3) proxy / contact points of the newest frames [m, scene coordinates]; live view.")
      .def_property_readonly("contacts", [](py::object self) {
        return latest_field<std::uint8_t>(self, [](const runtime::HapticFrame& f) { return &f.contact; }, 0);
      }, "(devices,) 1 where the newest frame is in contact; live view.")
      .def("body_positions", [](const Simulation& s, const py::object& body) -> py::object {
        const VecX* x = s.run->positions(index_of(body_names(*s.model), body, "body"));
        if (!x || x->size() == 0) return py::none();
        // A copy: the integrator may swap its position vector for another at the next step.
        py::array_t<double> a({static_cast<std::size_t>(x->size() / 3), std::size_t{3}});
        std::copy(x->data(), x->data() + x->size(), a.mutable_data());
        return a;
      }, py::arg("body"),
         "(nodes, 3) current positions of a body's simulation nodes [m] (a copy), or None for a body\n"
         "without dynamics (rigid, embedded, cspace).")
      .def("surface_positions", [](const Simulation& s, const py::object& body) -> py::object {
        const std::size_t b = index_of(body_names(*s.model), body, "body");
        const VecX* x = s.run->positions(b);
        if (!x || x->size() == 0) return py::none();
        const scene::Body& sb = s.model->bodies[b];
        // The surface's vertices are nodes of the body: through surface_to_volume for a
        // volumetric body, one for one otherwise (surface mass-spring, cloth).
        py::array_t<double> a({sb.surface.vertices.size(), std::size_t{3}});
        auto w = a.mutable_unchecked<2>();
        for (std::size_t i = 0; i < sb.surface.vertices.size(); ++i) {
          const auto node = static_cast<Eigen::Index>(sb.volume ? sb.surface_to_volume[i] : static_cast<mesh::Index>(i));
          for (py::ssize_t k = 0; k < 3; ++k) w(static_cast<py::ssize_t>(i), k) = (*x)[3 * node + k];
        }
        return a;
      }, py::arg("body"),
         "(surface vertices, 3) current positions of a body's surface [m] (a copy): with the body's\n"
         "Model triangles, its deformed surface mesh. None for a body without dynamics.")
      .def("set_material", [](Simulation& s, const py::object& body, double young_modulus,
                              const std::optional<double>& damping, const std::optional<double>& from_time) {
        s.live->set_material(index_of(body_names(*s.model), body, "body"), young_modulus, damping.value_or(-1.0),
                             from_time.value_or(s.run->time()));
      }, py::arg("body"), py::arg("young_modulus"), py::arg("damping") = std::nullopt, py::arg("from_time") = std::nullopt,
         "Edits a deformable body's Young's modulus [Pa] and, when given, its mass-proportional\n"
         "damping alpha [1/s], as the viewer's panel does (docs/viewer.md): the body's internal forces\n"
         "scale by E'/E, every law being linear in its moduli at a fixed Poisson ratio. The edit applies\n"
         "from simulated time from_time [s] (default: now), so a script edits at exact instants. Each\n"
         "call replaces the last; give the scene's modulus back to undo. Raises InputError for a body\n"
         "that cannot be edited (rigid, cspace, embedded) or a value out of range.")
      .def("set_surface", [](Simulation& s, const py::object& device, double stiffness, double static_friction,
                             double kinetic_friction, const std::optional<double>& from_time) {
        s.live->set_surface(index_of(device_names(*s.model), device, "device"), stiffness, static_friction,
                            kinetic_friction, from_time.value_or(s.run->time()));
      }, py::arg("device"), py::arg("stiffness"), py::arg("static_friction") = 0.0, py::arg("kinetic_friction") = 0.0,
         py::arg("from_time") = std::nullopt,
         "Edits a device's contact: the coupling stiffness [N/m] of its proxy or penalty plane (at most\n"
         "the device's max_stiffness) and the proxy's friction coefficients (kinetic <= static), from\n"
         "simulated time from_time [s] (default: now). Raises InputError for a contact without a\n"
         "stiffness to edit (Hertz, fingerpad, needle, multi-surface, configuration space).")
      .def("emergency_stop", [](Simulation& s) { s.run->emergency_stop(); },
           "Latches every device's emergency stop from the next step on.")
      .def_property_readonly("finished", [](const Simulation& s) { return s.run->finished(); })
      .def("finish", [](Simulation& s) {
        runtime::SessionReport report = s.run->finish();
        return make_run_result(std::move(report), *s.model);
      }, "Closes the recording and returns the RunResult (frames only with keep_frames=True).\n"
         "The live views stay readable; step() then raises RuntimeError.");
}

}  // namespace tactus::python
