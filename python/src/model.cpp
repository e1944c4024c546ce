// The scene Model (src/scene/model.hpp) as read-only Python objects. A Model is immutable
// once loaded; its parts (bodies, materials, ...) and the arrays over its meshes are views
// into it that keep it alive, never copies.
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <toml++/toml.h>

#include <algorithm>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>

#include "bindings.hpp"
#include "core/input_file.hpp"
#include "scene/scene.hpp"
#include "scene/scene_text.hpp"

namespace tactus::python {
namespace {

using Model = LoadedModel;

/// References to the items of `items`, each keeping `owner` (the object holding the vector) alive.
template <class T>
py::list references(const std::vector<T>& items, py::handle owner) {
  py::list out;
  for (const T& item : items) out.append(py::cast(&item, py::return_value_policy::reference_internal, owner));
  return out;
}

py::tuple vec3_tuple(const Vec3& v) { return py::make_tuple(v.x(), v.y(), v.z()); }

ModelHandle parse(const std::string& text, const std::string& name, bool allow_file_access) {
  scene::LoadOptions options;
  options.allow_file_access = allow_file_access;
  py::gil_scoped_release release;  // meshing a large scene takes seconds
  auto model = std::make_shared<Model>(Model{scene::parse_scene(text, name, options), text});
  return model;
}

/// A TOML node from a Python value: bool, int, float, str, a list of them, or a dict (a table).
toml::table table_of(const py::dict& d, const std::string& path);
toml::array array_of(const py::handle& list, const std::string& path);

template <class Insert>
void insert_value(const py::handle& v, const std::string& path, Insert&& insert) {
  if (py::isinstance<py::bool_>(v)) insert(v.cast<bool>());
  else if (py::isinstance<py::int_>(v)) insert(v.cast<std::int64_t>());
  else if (py::isinstance<py::float_>(v)) insert(v.cast<double>());
  else if (py::isinstance<py::str>(v)) insert(v.cast<std::string>());
  else if (py::isinstance<py::dict>(v)) insert(table_of(v.cast<py::dict>(), path));
  else if (py::isinstance<py::list>(v) || py::isinstance<py::tuple>(v)) insert(array_of(v, path));
  else
    throw py::type_error("'" + path + "': a scene value is a bool, int, float, str, list or dict, not " +
                         std::string(py::str(v.get_type().attr("__name__"))));
}

toml::table table_of(const py::dict& d, const std::string& path) {
  toml::table t;
  for (const auto& [key, value] : d) {
    const auto name = py::str(key).cast<std::string>();
    insert_value(value, path + "." + name, [&](auto&& x) { t.insert_or_assign(name, std::forward<decltype(x)>(x)); });
  }
  return t;
}

toml::array array_of(const py::handle& list, const std::string& path) {
  toml::array a;
  std::size_t i = 0;
  for (const auto& item : list)
    insert_value(item, path + "[" + std::to_string(i++) + "]", [&](auto&& x) { a.push_back(std::forward<decltype(x)>(x)); });
  return a;
}

/// The scene's text with `changes` ("table.sub.key": value) set: the tables along a path must
/// exist; a dict value merges key by key into a table already there (as a scene's `base`
/// does), any other value replaces or adds the key. The model is parsed again from that text.
ModelHandle with_changes(const Model& model, const py::dict& changes) {
  // The scene with its base chain merged in, so that every table a change names is there.
  scene::LoadOptions options;
  options.base_dir = std::filesystem::path(model.source).parent_path();
  toml::table root = scene::flatten_scene(model.text, model.source, options);
  for (const auto& [key, value] : changes) {
    const auto path = py::str(key).cast<std::string>();
    std::vector<std::string> parts;
    std::stringstream ss(path);
    for (std::string part; std::getline(ss, part, '.');) parts.push_back(part);
    if (parts.empty() || std::find(parts.begin(), parts.end(), std::string()) != parts.end())
      throw py::key_error("'" + path + "': a change names a key as table.sub.key");
    toml::table* table = &root;
    for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
      // The tables along the path must be there (a misspelt name would otherwise add a table
      // the loader then finds incomplete); a new table is a dict given to its parent.
      if (!table->contains(parts[i])) {
        std::string known;
        for (auto&& [k, node] : *table) known += (known.empty() ? "" : ", ") + std::string(k.str());
        throw py::key_error("'" + path + "': the scene has no table '" + parts[i] + "' there (it has: " + known + ")");
      }
      table = (*table)[parts[i]].as_table();
      if (!table)
        throw py::key_error("'" + path + "': '" + parts[i] + "' is not a table in the scene (an array of tables, such as a "
                            "body's [[fixed]] regions, is changed whole: give the list of dicts)");
    }
    toml::table* target = table;
    const std::string& last = parts.back();
    if (py::isinstance<py::dict>(value) && (*target)[last].as_table()) {
      scene::merge_tables(*(*target)[last].as_table(), table_of(value.cast<py::dict>(), path));
    } else {
      insert_value(value, path, [&](auto&& x) { target->insert_or_assign(last, std::forward<decltype(x)>(x)); });
    }
  }
  std::ostringstream text;
  text << "# " << model.source << " with changes made from Python\n" << scene::format_scene(root);
  // Relative paths (meshes) resolve against the original file's folder.
  const std::string source = model.source;
  const std::string new_text = text.str();
  py::gil_scoped_release release;
  return std::make_shared<Model>(Model{scene::parse_scene(new_text, source + " (changed)", options), new_text});
}

ModelHandle load(const std::filesystem::path& path) {
  // As `tactus run` reads it: the text kept for recordings, the path for messages.
  return parse(read_input_file(path.string()), path.string(), true);
}

}  // namespace

void bind_model(py::module_& m) {
  py::class_<scene::Material>(m, "Material", "A material of the scene ([materials.NAME]); elastic constants in Pa.")
      .def_readonly("name", &scene::Material::name)
      .def_property_readonly("model", [](const scene::Material& x) { return std::string(scene::model_name(x)); },
                             "The FEM law ('corotational', 'neo_hookean', ...) or 'mass_spring'.")
      .def_readonly("young_modulus", &scene::Material::young_modulus, "E [Pa]")
      .def_readonly("poisson_ratio", &scene::Material::poisson_ratio, "nu")
      .def_readonly("shear_modulus", &scene::Material::shear_modulus, "mu [Pa]")
      .def_readonly("bulk_modulus", &scene::Material::bulk_modulus, "kappa [Pa]")
      .def_readonly("lame_lambda", &scene::Material::lame_lambda, "lambda [Pa]")
      .def_readonly("c10", &scene::Material::c10, "Mooney-Rivlin C10 [Pa]")
      .def_readonly("c01", &scene::Material::c01, "Mooney-Rivlin C01 [Pa]")
      .def_readonly("density", &scene::Material::density, "[kg/m^3]")
      .def_property_readonly("rayleigh_alpha", [](const scene::Material& x) { return x.damping.rayleigh_alpha; })
      .def_property_readonly("rayleigh_beta", [](const scene::Material& x) { return x.damping.rayleigh_beta; })
      .def_property_readonly("nodal_damping", [](const scene::Material& x) { return x.damping.nodal; })
      .def_property_readonly("viscoelastic",
                             [](const scene::Material& x) { return std::string(scene::to_string(x.viscoelastic.model)); })
      .def("__repr__", [](const scene::Material& x) {
        return "<tactus.Material '" + x.name + "' " + std::string(scene::model_name(x)) + " E=" +
               std::to_string(x.young_modulus) + " nu=" + std::to_string(x.poisson_ratio) + ">";
      });

  py::class_<scene::FixedRegion>(m, "FixedRegion", "Nodes held fixed ([[bodies.NAME.fixed]]).")
      .def_readonly("name", &scene::FixedRegion::name)
      .def_readonly("selector", &scene::FixedRegion::selector)
      .def_property_readonly("nodes", [](py::object self) {
        return vector_view(self.cast<const scene::FixedRegion&>().nodes, self);
      }, "Node indices into the body's simulation nodes (int32, read-only view).");

  py::class_<scene::Probe>(m, "Probe", "A named point whose displacement solves report.")
      .def_readonly("name", &scene::Probe::name)
      .def_property_readonly("position", [](const scene::Probe& p) { return vec3_tuple(p.position); });

  py::class_<scene::Body>(m, "Body", "A body of the scene ([bodies.NAME]) with its meshes.")
      .def_readonly("name", &scene::Body::name)
      .def_property_readonly("kind", [](const scene::Body& b) { return std::string(scene::to_string(b.kind)); },
                             "'surface_mass_spring', 'tet_mass_spring', 'fem', 'rigid' or 'embedded'.")
      .def_readonly("material_index", &scene::Body::material, "Index into Model.materials, or None.")
      .def_readonly("mesh_source", &scene::Body::mesh_source)
      .def_property_readonly("volumetric", &scene::Body::volumetric)
      .def_property_readonly("node_count", [](const scene::Body& b) { return b.simulation_vertices().size(); },
                             "Simulation nodes: the tet mesh's for volumetric bodies, else the surface's.")
      .def_property_readonly("surface_vertex_count", [](const scene::Body& b) { return b.surface.vertices.size(); })
      .def_property_readonly("triangle_count", [](const scene::Body& b) { return b.surface.triangles.size(); })
      .def_property_readonly("tet_count", [](const scene::Body& b) { return b.volume ? b.volume->tets.size() : 0; })
      .def_property_readonly("rest_positions", [](py::object self) {
        return vec3_view(self.cast<const scene::Body&>().simulation_vertices(), self);
      }, "(node_count, 3) float64 rest positions of the simulation nodes [m]; a read-only view.")
      .def_property_readonly("surface_vertices", [](py::object self) {
        return vec3_view(self.cast<const scene::Body&>().surface.vertices, self);
      }, "(n, 3) float64 rest surface vertices [m]; a read-only view.")
      .def_property_readonly("triangles", [](py::object self) {
        return index_view(self.cast<const scene::Body&>().surface.triangles, self);
      }, "(n, 3) int32 surface triangles; a read-only view.")
      .def_property_readonly("tets", [](py::object self) -> py::object {
        const auto& b = self.cast<const scene::Body&>();
        if (!b.volume) return py::none();
        return index_view(b.volume->tets, self);
      }, "(n, 4) int32 tetrahedra of a volumetric body (None otherwise); a read-only view.")
      .def_property_readonly("fixed", [](py::object self) { return references(self.cast<const scene::Body&>().fixed, self); })
      .def_property_readonly("probes", [](py::object self) { return references(self.cast<const scene::Body&>().probes, self); })
      .def_readonly("time_step", &scene::Body::time_step, "[s]")
      .def_property_readonly("integrator", [](const scene::Body& b) { return std::string(scene::to_string(b.stepping.integrator)); })
      .def("__repr__", [](const scene::Body& b) {
        return "<tactus.Body '" + b.name + "' " + scene::to_string(b.kind) + ", " +
               std::to_string(b.simulation_vertices().size()) + " nodes>";
      });

  py::class_<scene::Device>(m, "Device", "A haptic device of the scene ([devices.NAME]).")
      .def_readonly("name", &scene::Device::name)
      .def_property_readonly("kind", [](const scene::Device& d) { return std::string(scene::device_type_name(d.source)); })
      .def_readonly("max_force", &scene::Device::max_force, "[N]")
      .def_readonly("max_stiffness", &scene::Device::max_stiffness, "[N/m]")
      .def_readonly("scale", &scene::Device::scale)
      .def_property_readonly("offset", [](const scene::Device& d) { return vec3_tuple(d.offset); }, "[m]")
      .def("__repr__", [](const scene::Device& d) {
        return "<tactus.Device '" + d.name + "' " + scene::device_type_name(d.source) + ">";
      });

  py::class_<scene::Tool>(m, "Tool", "What touches the tissue ([tools.NAME]).")
      .def_readonly("name", &scene::Tool::name)
      .def_property_readonly("kind", [](const scene::Tool& t) { return std::string(scene::tool_type_name(t.shape)); })
      .def_readonly("device_indices", &scene::Tool::devices, "Indices into Model.devices.")
      .def_property_readonly("radius", [](const scene::Tool& t) -> py::object {
        if (const auto* s = std::get_if<scene::SphereTool>(&t.shape)) return py::float_(s->radius);
        if (const auto* s = std::get_if<scene::TwoFingersTool>(&t.shape)) return py::float_(s->radius);
        return py::none();
      }, "Sphere radius [m] of a 'sphere' or 'two_fingers' tool; None for the others.")
      .def("__repr__", [](const scene::Tool& t) {
        return "<tactus.Tool '" + t.name + "' " + scene::tool_type_name(t.shape) + ">";
      });

  py::class_<scene::Algorithm>(m, "Algorithm", "A force algorithm ([algorithms.NAME]).")
      .def_readonly("name", &scene::Algorithm::name)
      .def_property_readonly("kind", [](const scene::Algorithm& a) { return std::string(scene::algorithm_type_name(a.params)); })
      .def_readonly("tool_index", &scene::Algorithm::tool)
      .def_readonly("body_indices", &scene::Algorithm::bodies, "Indices into Model.bodies; empty = every body.")
      .def_readonly("enabled", &scene::Algorithm::enabled);

  py::class_<Model, ModelHandle>(m, "Model",
                                 "A loaded scene (immutable). Its parts and arrays are views that keep it alive.")
      .def_readonly("name", &scene::Model::name)
      .def_readonly("description", &scene::Model::description)
      .def_readonly("source", &scene::Model::source, "The file (or name) it was loaded from.")
      .def_readonly("text", &Model::text, "The scene text it was parsed from.")
      .def_property_readonly("gravity", [](const Model& x) { return vec3_tuple(x.gravity); }, "[m/s^2]")
      .def_property_readonly("rates", [](const Model& x) {
        py::dict d;
        d["haptic"] = x.rates.haptic;
        d["simulation"] = x.rates.simulation;
        d["interaction"] = x.rates.interaction;
        d["visual"] = x.rates.visual;
        return d;
      }, "Loop rates [Hz] by loop name.")
      .def_property_readonly("materials", [](py::object self) { return references(self.cast<const Model&>().materials, self); })
      .def_property_readonly("bodies", [](py::object self) { return references(self.cast<const Model&>().bodies, self); })
      .def_property_readonly("devices", [](py::object self) { return references(self.cast<const Model&>().devices, self); })
      .def_property_readonly("tools", [](py::object self) { return references(self.cast<const Model&>().tools, self); })
      .def_property_readonly("algorithms", [](py::object self) { return references(self.cast<const Model&>().algorithms, self); })
      .def("body", [](py::object self, const std::string& name) {
        const scene::Body* b = self.cast<const Model&>().find_body(name);
        if (!b) throw py::key_error("no body '" + name + "'");
        return py::cast(b, py::return_value_policy::reference_internal, self);
      }, py::arg("name"), "The body of this name (KeyError if none).")
      .def("material", [](py::object self, const std::string& name) {
        const scene::Material* x = self.cast<const Model&>().find_material(name);
        if (!x) throw py::key_error("no material '" + name + "'");
        return py::cast(x, py::return_value_policy::reference_internal, self);
      }, py::arg("name"), "The material of this name (KeyError if none).")
      .def("material_of", [](py::object self, const scene::Body& b) -> py::object {
        if (!b.material) return py::none();
        return py::cast(&self.cast<const Model&>().materials.at(*b.material), py::return_value_policy::reference_internal, self);
      }, py::arg("body"), "The material of a body of this model, or None.")
      .def("with_changes", &with_changes, py::arg("changes"),
           "A new Model: this scene with changes made before it is compiled, as a dict of\n"
           "'table.sub.key': value (bool, int, float, str, list, or a dict merged key by key into the\n"
           "table there), e.g. {'materials.block.young_modulus': 40e3, 'rates.haptic': 2000}. The scene\n"
           "text is changed and parsed again (its text() holds the result, so recordings replay it);\n"
           "an unknown key or a bad value raises tactus.InputError naming the key path.")
      .def("summary", [](const Model& x, bool real_time) { return scene::summarize(x, real_time); },
           py::arg("real_time") = true, "The multi-line summary `tactus inspect SCENE` prints.")
      .def("__repr__", [](const Model& x) {
        return "<tactus.Model '" + x.name + "' from '" + x.source + "': " + std::to_string(x.bodies.size()) +
               " bodies, " + std::to_string(x.devices.size()) + " devices>";
      });

  m.def("load_scene", &load, py::arg("path"),
        "Reads and validates a scene file (docs/scene-format.md). Raises tactus.InputError.");
  m.def("parse_scene", &parse, py::arg("text"), py::arg("name") = "<python>", py::arg("allow_file_access") = true,
        "Parses scene text; `name` is the file name in messages and the anchor of relative paths.\n"
        "allow_file_access=False refuses any key naming a file. Raises tactus.InputError.");
  m.def("default_scene", [] { return parse(std::string(scene::default_scene_text()), "<built-in default scene>", true); },
        "The built-in default scene (scenes/default.toml).");
}

}  // namespace tactus::python
