#include "scene/model.hpp"

#include <algorithm>

namespace tactus::scene {

namespace {

template <class T>
const T* find_named(const std::vector<T>& items, std::string_view name) {
  auto it = std::find_if(items.begin(), items.end(), [&](const T& x) { return x.name == name; });
  return it == items.end() ? nullptr : &*it;
}

template <class... Ts>
struct Overload : Ts... {
  using Ts::operator()...;
};
template <class... Ts>
Overload(Ts...) -> Overload<Ts...>;

}  // namespace

const Material* Model::find_material(std::string_view n) const { return find_named(materials, n); }
const Body* Model::find_body(std::string_view n) const { return find_named(bodies, n); }
const Device* Model::find_device(std::string_view n) const { return find_named(devices, n); }
const Tool* Model::find_tool(std::string_view n) const { return find_named(tools, n); }
const Algorithm* Model::find_algorithm(std::string_view n) const { return find_named(algorithms, n); }

std::string_view model_name(const Material& m) { return m.law ? physics::to_string(*m.law) : "mass_spring"; }

const char* to_string(ViscoelasticModel m) {
  switch (m) {
    case ViscoelasticModel::none: return "none";
    case ViscoelasticModel::kelvin_voigt: return "kelvin_voigt";
    case ViscoelasticModel::standard_linear_solid: return "standard_linear_solid";
    case ViscoelasticModel::prony: return "prony";
  }
  return "?";
}

const char* to_string(BodyKind k) {
  switch (k) {
    case BodyKind::surface_mass_spring: return "surface_mass_spring";
    case BodyKind::tet_mass_spring: return "tet_mass_spring";
    case BodyKind::fem: return "fem";
    case BodyKind::rigid: return "rigid";
    case BodyKind::embedded: return "embedded";
    case BodyKind::cloth: return "cloth";
  }
  return "?";
}

const char* to_string(physics::Integrator i) {
  switch (i) {
    case physics::Integrator::explicit_euler: return "explicit_euler";
    case physics::Integrator::symplectic_euler: return "symplectic_euler";
    case physics::Integrator::rk4: return "rk4";
    case physics::Integrator::implicit_euler: return "implicit_euler";
  }
  return "?";
}

const char* to_string(physics::LinearSolver s) { return s == physics::LinearSolver::cholesky ? "cholesky" : "cg"; }
const char* to_string(MassMatrix m) { return m == MassMatrix::lumped ? "lumped" : "consistent"; }

const char* to_string(MappedRole r) {
  switch (r) {
    case MappedRole::visual: return "visual";
    case MappedRole::collision: return "collision";
    case MappedRole::embedded: return "embedded";
  }
  return "?";
}

const char* to_string(SpringType s) {
  switch (s) {
    case SpringType::longitudinal: return "longitudinal";
    case SpringType::diagonal: return "diagonal";
    case SpringType::torsional: return "torsional";
    case SpringType::bending: return "bending";
  }
  return "?";
}

const char* tool_type_name(const ToolShape& s) {
  return std::visit(Overload{[](const SphereTool&) { return "sphere"; },
                             [](const SphereSetTool&) { return "sphere_set"; },
                             [](const NeedleTool&) { return "needle"; },
                             [](const TwoFingersTool&) { return "two_fingers"; }},
                    s);
}

const char* device_type_name(const DeviceSource& s) {
  return std::visit(Overload{[](const ScriptedDevice&) { return "scripted"; },
                             [](const SimulatedOperatorDevice&) { return "simulated_operator"; },
                             [](const ReplayDevice&) { return "replay"; },
                             [](const NetworkDevice&) { return "network"; },
                             [](const OpenHapticsDevice&) { return "openhaptics"; },
                             [](const DhdDevice&) { return "dhd"; }},
                    s);
}

const char* trajectory_type_name(const Trajectory& t) {
  return std::visit(Overload{[](const WaypointsPath&) { return "waypoints"; },
                             [](const RasterPath&) { return "raster"; },
                             [](const PressPath&) { return "press"; },
                             [](const CirclePath&) { return "circle"; },
                             [](const NeedleLinePath&) { return "needle_line"; }},
                    t);
}

const char* algorithm_type_name(const AlgorithmParams& p) {
  return std::visit(Overload{[](const ProxyParams&) { return "proxy"; },
                             [](const HertzFingerParams&) { return "hertz_finger"; },
                             [](const FingerpadParams&) { return "fingerpad"; },
                             [](const MultiSurfaceParams&) { return "multi_surface"; },
                             [](const PulseParams&) { return "pulse"; },
                             [](const NeedleParams&) { return "needle"; },
                             [](const FabricProxyParams&) { return "fabric_proxy"; }},
                    p);
}

}  // namespace tactus::scene
