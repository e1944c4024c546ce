#pragma once
// The immutable Model a scene file describes: plain structs in SI units (m, kg, s, N, Pa).
// A Model is built once by the loader and then only read; share it as ModelPtr.
// docs/scene-format.md documents every field as the key that sets it.
#include <cstddef>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "contact/fabric_proxy.hpp"
#include "contact/finger_contact.hpp"
#include "contact/grasp.hpp"
#include "contact/hertz.hpp"
#include "contact/local_model_kind.hpp"
#include "contact/proxy.hpp"
#include "core/math.hpp"
#include "haptics/algorithms/multi_surface.hpp"
#include "haptics/algorithms/pulse.hpp"
#include "haptics/algorithms/needle.hpp"
#include "haptics/trajectory.hpp"
#include "lod/impostors.hpp"
#include "mesh/generators.hpp"
#include "mesh/tet_mesh.hpp"
#include "mesh/tri_mesh.hpp"
#include "physics/cloth/cloth_model.hpp"
#include "physics/fem/material.hpp"
#include "physics/mapping.hpp"
#include "physics/step_settings.hpp"
#include "precompute/settings.hpp"
#include "property_images/property_images.hpp"

namespace tactus::scene {

// ---------------------------------------------------------------------------------------
// Loop rates [Hz]

struct LoopRates {
  double haptic = 1000.0;      ///< [100, 10000]
  double simulation = 100.0;   ///< [1, 1000]
  double interaction = 120.0;  ///< [1, 1000]
  double visual = 60.0;        ///< [1, 240]
  /// In real time, the most periods one late simulation step may span: a step that starts
  /// after missed periods advances its implicit bodies over the time since the last step, up
  /// to this many periods, so that the simulation keeps the hand's time on a machine too slow
  /// for its rate. 1 steps one period whatever the lateness. [1, 10]
  double catch_up = 1.0;
};

/// How the real-time scheduler asks the operating system for timing (docs/realtime.md);
/// lockstep runs ignore it. Command-line flags override it.
struct RealtimeSettings {
  int priority = 80;       ///< SCHED_FIFO priority of the haptic threads; 0 = normal scheduler
  int haptic_cpu = -1;     ///< pin the haptic threads to this CPU; −1 = no pinning
  double spin = 50e-6;     ///< [s] the last part of each haptic wait spins instead of sleeping
  /// The haptic threads never sleep: they spin through the whole period (give them a core).
  bool dedicated_core = false;
};

// ---------------------------------------------------------------------------------------
// Materials


struct Damping {
  double rayleigh_alpha = 0.0;  ///< mass-proportional [1/s]
  double rayleigh_beta = 0.0;   ///< stiffness-proportional [s]
  double nodal = 0.0;           ///< per-node absolute-velocity damping (seed 000 d_i) [N·s/m]
};

enum class ViscoelasticModel { none, kelvin_voigt, standard_linear_solid, prony };

/// One term of a Prony series: relative modulus g_i of a Maxwell branch and its relaxation
/// time τ_i. The long-term modulus is E·(1 − Σ g_i).
struct PronyTerm {
  double g = 0.0;    ///< (0, 1)
  double tau = 0.0;  ///< [s], > 0
};

struct Viscoelasticity {
  ViscoelasticModel model = ViscoelasticModel::none;
  /// kelvin_voigt: retardation time η/E (creep); standard_linear_solid: relaxation time [s].
  double tau = 0.0;
  /// standard_linear_solid: E_∞ / E_0, in (0, 1); 1 otherwise.
  double long_term_fraction = 1.0;
  std::vector<PronyTerm> prony;  ///< prony only
};

/// Elastic constants are always all filled in, whichever pair the file gave.
struct Material {
  std::string name;
  /// The FEM law (`model = "..."`); none for a spring material (`model = "mass_spring"`).
  std::optional<physics::FemLaw> law = physics::FemLaw::corotational;
  double young_modulus = 0.0;  ///< E [Pa]
  double poisson_ratio = 0.0;  ///< ν, in (−1, 0.5)
  double shear_modulus = 0.0;  ///< μ [Pa]
  double bulk_modulus = 0.0;   ///< κ [Pa]
  double lame_lambda = 0.0;    ///< λ [Pa]
  /// Mooney–Rivlin constants [Pa] (W = C10 (Ī1 − 3) + C01 (Ī2 − 3) + κ/2 (J − 1)²);
  /// for every other model C10 = μ/2 and C01 = 0.
  double c10 = 0.0;
  double c01 = 0.0;
  double density = 0.0;  ///< [kg/m³]
  Damping damping;
  Viscoelasticity viscoelastic;
  /// `volumetric = "nodal"` (Mooney–Rivlin): κ/2 (J̄ − 1)² with J̄ the volume change averaged
  /// at the nodes, not per element (physics/fem/nodal_pressure.hpp).
  bool nodal_pressure = false;
};

// ---------------------------------------------------------------------------------------
// Bodies

/// embedded: a surface carried by another body's tetrahedra (seed 003 §3.1: a fascia sheet,
/// a vessel wall inside the behaviour mesh); it has no dynamics of its own.
enum class BodyKind { surface_mass_spring, tet_mass_spring, fem, rigid, embedded, cloth };
enum class MassMatrix { lumped, consistent };
enum class SpringType { longitudinal, diagonal, torsional, bending };

/// Nodes held fixed. `selector` says how they were chosen, for summaries and messages.
struct FixedRegion {
  std::string name;
  std::string selector;             ///< e.g. "side z_min", "box", "nodes", "marker 3"
  std::vector<mesh::Index> nodes;   ///< sorted, unique, never empty
};

/// A constant external force, shared equally by the selected nodes; it ramps in linearly
/// over ramp_time in dynamic runs (0 = a step).
struct NodeLoad {
  std::string name;
  std::string selector;
  std::vector<mesh::Index> nodes;  ///< sorted, unique, never empty
  Vec3 force = Vec3::Zero();       ///< total [N]
  double ramp_time = 0.0;          ///< [s]
};

/// Nodes moved by a prescribed displacement from rest (a point or patch indentation).
struct PrescribedMotion {
  std::string name;
  std::string selector;
  std::vector<mesh::Index> nodes;  ///< sorted, unique, never empty
  Vec3 displacement = Vec3::Zero();  ///< final [m]
  double ramp_time = 0.0;            ///< [s]; dynamic runs ramp linearly, static runs use load_steps
};

enum class MappedRole { visual, collision, embedded };

/// A surface carried by a tetrahedral body (seed 003 §3.1): a finer visual skin, a separate
/// collision surface, or a structure embedded in the volume (a vessel tube, a fascia sheet).
/// Each vertex follows the tetrahedron that holds it at rest by barycentric weights; forces
/// on the vertices go back to the body's nodes by the transpose.
struct MappedSurface {
  std::string name;
  MappedRole role = MappedRole::visual;
  std::string source;  ///< the mesh file or generator call
  mesh::TriMesh mesh;  ///< rest positions
  /// The mapping into the body's tet mesh, computed at load time.
  std::shared_ptr<const physics::BarycentricMapping> mapping;
};

/// A named point in the rest configuration whose displacement is reported.
struct Probe {
  std::string name;
  Vec3 position = Vec3::Zero();  ///< [m]
};

/// A sphere under a surface sheet that the sheet touches only from outside (seed 004): rigid
/// (nodes are projected onto it) or soft (it pushes back with its Hertz pressure).
struct Nodule {
  std::string name;
  Vec3 center = Vec3::Zero();  ///< [m]
  double radius = 0.0;         ///< [m]
  bool rigid = true;
  double young_modulus = 0.0;  ///< [Pa], soft only
  double poisson_ratio = 0.45; ///< soft only
};

/// kind = "cloth": a woven fabric (seed 002 §III-B) on a warp/weft sheet or a mesh file.
struct Cloth {
  std::string fabric;         ///< the database key, or empty for the scene's own curves
  std::string fabric_source;  ///< the database file (or the scene) the values came from
  bool illustrative = false;  ///< the database marks the values as not measured
  /// The fabric, built (and so checked) once at load: its material, rest mesh and bends.
  std::shared_ptr<const physics::ClothModel> model;
  int nodes_u = 0, nodes_v = 0;  ///< a generated sheet's nodes along warp and weft (0: a mesh file)
  double static_friction = 0.5, kinetic_friction = 0.4;  ///< against skin
};

/// [bodies.X.levels]: how the impostor levels are built and switched.
struct SurfaceLevels {
  lod::ImpostorParams build;
  /// A level file written ahead (a `[lod] cache` entry): read instead of built, and refused
  /// when made for another mesh or other parameters (empty: built, or from the cache).
  std::filesystem::path file;
  double raise_force = 2.0;  ///< N: above it, the touched object's level goes one finer
  double lower_force = 1.0;  ///< N: below it for hold_time, one coarser
  double hold_time = 0.1;    ///< s
};

/// [bodies.X.properties]: property images cast from the body's surface (or read from `file`)
/// and strokes painted on them at load.
struct SurfacePropertyImages {
  int resolution = 128;  ///< pixels along the surface's longest side
  property_images::SurfaceProperties base;
  std::filesystem::path file;  ///< a saved image file (empty: cast at load)
  struct Stroke {
    Vec3 center = Vec3::Zero();
    double radius = 0.0;
    property_images::SurfaceProperties values;
    property_images::ChannelMask mask = 0;
  };
  std::vector<Stroke> paint;
  SourceLocation where;  ///< the table, for errors found when the images are built
};

struct Body {
  std::string name;
  BodyKind kind = BodyKind::fem;
  /// Index into Model::materials; empty only for a rigid body given no material.
  std::optional<std::size_t> material;
  /// fem bodies: the materials of the volume mesh's regions (its tet_regions tags, e.g. a
  /// label image's labels), tag → index into Model::materials; tags not listed take
  /// `material`. The regions share the law, damping and viscoelasticity (checked at load).
  std::vector<std::pair<int, std::size_t>> region_materials;
  /// Where the mesh came from: the resolved file path or the generator call.
  std::string mesh_source;

  /// Collision and display surface (always present). For volumetric bodies it is the
  /// boundary of `volume` with its own compact numbering (see surface_to_volume).
  mesh::TriMesh surface;
  /// Tetrahedral mesh of tet_mass_spring and fem bodies.
  std::optional<mesh::TetMesh> volume;
  /// Surface vertex → volume vertex (volumetric bodies only).
  std::vector<mesh::Index> surface_to_volume;
  /// The quad sheet of a surface mass-spring made by the grid_plate generator with
  /// quads = true; its vertices are the surface's vertices.
  std::optional<mesh::QuadMesh> quads;

  std::vector<FixedRegion> fixed;  ///< node indices into simulation_vertices()
  std::vector<NodeLoad> loads;
  std::vector<PrescribedMotion> prescribed;
  std::vector<Probe> probes;
  std::vector<MappedSurface> mapped;  ///< volumetric bodies only
  std::vector<Nodule> nodules;  ///< surface_mass_spring only
  int load_steps = 1;  ///< static solves apply loads and prescribed motions in this many steps
  /// kind = "cspace": an FEM body whose haptic force and shape come from a precomputed
  /// configuration space (docs/precompute.md) instead of a simulation.
  struct ConfigurationSpace {
    std::filesystem::path file;  ///< the .h5 file `tactus precompute` wrote (empty when online)
    precompute::Interpolation interpolation = precompute::Interpolation::trilinear;
    /// Built on-line during the run from the scene's [precompute] table instead of read from
    /// a file: solver threads work around the tool and ahead of it (precompute/online.hpp).
    bool online = false;
    int workers = 1;  ///< online: solver threads
    /// A two-point space (precompute/pair.hpp): the tools at its first and second point
    /// (indices into Model::tools, each on its own device); empty for a space of one point.
    std::vector<std::size_t> tools;
  };
  std::optional<ConfigurationSpace> cspace;
  /// kind = "embedded": the volumetric body whose tetrahedra carry this surface (an earlier
  /// index into Model::bodies is not guaranteed) and the mapping of `surface`'s rest vertices
  /// into them. Loads on the surface go to the host's nodes by the mapping's transpose.
  std::optional<std::size_t> host;
  std::shared_ptr<const physics::BarycentricMapping> host_mapping;
  std::optional<Cloth> cloth;  ///< kind = "cloth"
  /// [bodies.X.levels] (rigid bodies): a hierarchy of impostors of the surface that the
  /// haptic loop chooses among and switches by force (seed 000 §4; lod/, docs/lod.md).
  std::optional<SurfaceLevels> levels;
  /// [bodies.X.properties] (rigid bodies): the surface material per pixel of six depth images
  /// (seed 001, second chapter; property_images/, docs/property-images.md).
  std::optional<SurfacePropertyImages> properties;

  // Time stepping (deformable bodies): the integrator, the linear solver and its tolerances,
  // the Newton iterations of an implicit step.
  physics::StepSettings stepping;
  double time_step = 0.01;  ///< [s]
  MassMatrix mass_matrix = MassMatrix::lumped;
  std::vector<SpringType> springs;  ///< surface_mass_spring only
  /// surface_mass_spring only: sheet thickness [m]; with the material it sets the spring
  /// stiffnesses and the areal density (docs/scene-format.md gives the rules).
  double thickness = 0.001;

  [[nodiscard]] bool volumetric() const {
    return kind == BodyKind::tet_mass_spring || kind == BodyKind::fem;
  }
  /// The nodes the physics moves: the tet mesh's for volumetric bodies, else the surface's.
  [[nodiscard]] const std::vector<Vec3>& simulation_vertices() const {
    return volumetric() ? volume->vertices : surface.vertices;
  }
};

// ---------------------------------------------------------------------------------------
// Tools (what touches the tissue)

struct Sphere {
  Vec3 center = Vec3::Zero();  ///< offset from the tool frame [m]
  double radius = 0.0;         ///< [m]
};

/// Elastic sphere(s) with a silicone-rubber default (seed 000's finger).
struct FingerProperties {
  double mass = 0.01;             ///< whole finger [kg]
  double young_modulus = 1.0e6;   ///< [Pa]
  double poisson_ratio = 0.48;
};

struct SphereTool {
  double radius = 0.008;
  FingerProperties finger;
};
/// 1 or 8 spheres (seed 000 Fig. 1), resolved to offsets in the tool frame.
struct SphereSetTool {
  std::vector<Sphere> spheres;
  FingerProperties finger;
};
struct NeedleTool {
  double length = 0.08;      ///< [m]
  double diameter = 0.0013;  ///< [m]
  double mass = 0.005;       ///< [kg]
};
/// Two fingertip spheres (seed 002), each driven by its own device.
struct TwoFingersTool {
  double radius = 0.008;
  FingerProperties finger;  ///< per finger
};

using ToolShape = std::variant<SphereTool, SphereSetTool, NeedleTool, TwoFingersTool>;

struct Tool {
  std::string name;
  ToolShape shape;
  /// Indices into Model::devices: one, or two for two_fingers (first, second).
  std::vector<std::size_t> devices;
};

// ---------------------------------------------------------------------------------------
// Devices

// Trajectories and tremor are haptics:: types (the scripted devices evaluate them).
using haptics::CirclePath;
using haptics::NeedleLinePath;
using haptics::PressPath;
using haptics::RasterPath;
using haptics::Trajectory;
using haptics::Tremor;
using haptics::Waypoint;
using haptics::WaypointsPath;

struct ScriptedDevice {
  Trajectory trajectory;
  Tremor tremor;
};
/// A hand model (mass-spring-damper) coupling the handle to a scripted target.
struct SimulatedOperatorDevice {
  Trajectory target;
  Tremor tremor;
  double hand_mass = 0.2;        ///< [kg]
  double hand_stiffness = 300.0; ///< [N/m]
  double hand_damping = 5.0;     ///< [N·s/m]
};
struct ReplayDevice {
  std::filesystem::path file;  ///< resolved against the scene's folder
};
struct NetworkDevice {
  std::string address = "127.0.0.1";
  int port = 47600;
  double timeout = 0.05;  ///< force fades to zero after this long without packets [s]
};
/// A physical device through its vendor's SDK (built only where the SDK was found).
struct OpenHapticsDevice {
  std::string device_name;  ///< as configured in Geomagic Touch Setup; empty = the default device
};
struct DhdDevice {
  int index = -1;  ///< Force Dimension device index; −1 = the first one found
};
using DeviceSource = std::variant<ScriptedDevice, SimulatedOperatorDevice, ReplayDevice, NetworkDevice,
                                  OpenHapticsDevice, DhdDevice>;

struct Device {
  std::string name;
  DeviceSource source;
  double max_force = 10.0;        ///< [N]
  double max_stiffness = 2000.0;  ///< [N/m]
  /// The strongest damping the device renders: the passivity controller damps no harder [N·s/m].
  double max_damping = 100.0;
  Aabb workspace;                 ///< in device coordinates [m]
  double scale = 1.0;             ///< device → scene: p_scene = scale · p_device + offset
  Vec3 offset = Vec3::Zero();
  Quat rotation = Quat::Identity();  ///< device axes → scene axes, applied before scale
};

// ---------------------------------------------------------------------------------------
// Force algorithms

/// God-object / proxy with virtual coupling and Coulomb friction.
struct ProxyParams {
  double stiffness = contact::ProxyParams{}.stiffness;  ///< [N/m]
  double damping = contact::ProxyParams{}.damping;      ///< [N·s/m]
  double static_friction = contact::ProxyParams{}.static_friction;
  double kinetic_friction = contact::ProxyParams{}.kinetic_friction;
};
/// Body-based finger: Hertz contact per sphere with dynamic curvature (seed 000).
struct HertzFingerParams {
  int curvature_rings = 2;  ///< q-ring neighbourhood of the curvature vote
  double friction = 0.2;
  bool weight_compensation = true;
};
/// Pawluk & Howe fingerpad law F = (b/m)(e^(m·d) − 1) (seed 002 eq. 1).
struct FingerpadParams {
  double b = contact::FingerpadParameters{}.b;  ///< [N/m]
  double m = contact::FingerpadParameters{}.m;  ///< [1/m]
  bool quasilinear_viscoelastic = false;
};
/// Constraint planes at every surface hit along the tool ray (seed 003 §3.5); the layers
/// are the algorithm's bodies, outermost first.
struct MultiSurfaceParams {
  double stiffness = haptics::MultiSurfaceConfig{}.stiffness;  ///< [N/m]
  double damping = haptics::MultiSurfaceConfig{}.damping;      ///< [N·s/m]
  double static_friction = haptics::MultiSurfaceConfig{}.static_friction;    ///< tissue dragging: μs (0 = frictionless)
  double kinetic_friction = haptics::MultiSurfaceConfig{}.kinetic_friction;  ///< μk ≤ μs
};
/// The V-proxy of a fingertip on a fabric (seed 002 §V-C): a god-object that keeps to its
/// side of the thin sheet, with stick–slip friction, on the fabric's local patch.
struct FabricProxyParams {
  double stiffness = 190.0;  ///< k^K, finger and fabric in series [N/m] (the fingerpad's slope at first touch)
  /// μs, μk against the fabric; unset: the fabric's own (its database entry or `friction`).
  std::optional<double> static_friction, kinetic_friction;
  int side = +1;             ///< +1: the front, where the fabric's normals point (thumb); −1: the back (index)
  double mass = contact::FabricProxyParams{}.mass;        ///< the proxy's while it slides [kg]
  double damping = contact::FabricProxyParams{}.damping;  ///< [N·s/m]
  /// The other fingertip of a two-finger pair (seed 002 §V: thumb and index), an index into
  /// Model::tools; its own fabric_proxy algorithm names this one's tool back, on the other
  /// side. With a partner the fingers also touch each other and grasp the fabric between them.
  std::optional<std::size_t> partner;
  /// The pad's side of the fingertip in the tool frame (the grasp takes the pad as flat).
  Vec3 pad_normal = Vec3::Zero();
  double fabric_thickness = contact::GraspParams{}.fabric_thickness;  ///< squeezed once the pads are closer [m]
  /// Skin on skin, fingers touching without fabric between them (μs, μk).
  double finger_static_friction = contact::FingerContactParams{}.static_friction;
  double finger_kinetic_friction = contact::FingerContactParams{}.kinetic_friction;
};
/// Rectangular pulse wave from point sources along a body (an artery).
struct PulseParams {
  std::size_t body = 0;       ///< index into Model::bodies
  double rate = haptics::PulseConfig{}.rate;              ///< [beats/min], [30, 200]
  double duty_cycle = haptics::PulseConfig{}.duty_cycle;  ///< (0, 1)
  double amplitude = haptics::PulseConfig{}.amplitude;    ///< [N]
  int sources = 10;                                       ///< point sources along the body
  double range = haptics::PulseConfig{}.range;            ///< distance over which the pulse fades [m]
};
/// A layer the needle pierces (haptics/algorithms/needle.hpp): a body, its rupture
/// threshold, its stiffness before rupture and its shaft friction after.
using haptics::NeedleLayer;
struct NeedleParams {
  double lateral_stiffness = 200.0;  ///< spring towards the puncture path, whole shaft inside [N/m]
  /// As listed under `layers`, or one layer with default values per body of the algorithm.
  std::vector<NeedleLayer> layers;
};
using AlgorithmParams = std::variant<ProxyParams, HertzFingerParams, FingerpadParams,
                                     MultiSurfaceParams, PulseParams, NeedleParams, FabricProxyParams>;

/// How the contact force is shared among the tissue's nodes (contact/load_spread.hpp): by
/// the contact triangle's barycentric weights, or over the contact disc.
enum class LoadSpread { triangle, contact_disc };

struct Algorithm {
  std::string name;
  std::size_t tool = 0;              ///< index into Model::tools
  std::vector<std::size_t> bodies;   ///< indices into Model::bodies; empty = every body
  bool enabled = true;
  AlgorithmParams params;
  /// The local mass-spring patch errs least against a simulation at the haptic rate
  /// (tests/scenarios/local_model_choice_test.cpp).
  /// What the haptic loop renders between simulation steps (docs/runtime.md): a contact
  /// plane, the patch nodes' condensed compliance, or a local mass-spring patch (seed 002 §IV).
  contact::LocalModelKind local_model = contact::LocalModelKind::mass_spring;
  /// Fastest tool motion the local patch must cover between two simulation steps [m/s].
  double max_tool_speed = 0.2;
  /// Time constant over which a force step at a model update is smoothed out, passively [s];
  /// 0 = off.
  double force_smoothing = 0.0;
  LoadSpread load_spread = LoadSpread::triangle;
  /// Keep the contact from returning more energy to the hand than the hand put in
  /// (haptics/passivity_control.hpp).
  bool passivity_control = true;
};

// ---------------------------------------------------------------------------------------
// Recording

// ---------------------------------------------------------------------------------------
// Static solves

/// [solve]: how `tactus solve --static` balances each load step.
struct StaticSolve {
  physics::StaticSettings newton{100, 1e-8, 1e-10};
  /// A load step whose solve fails (no convergence, or an element inside out) is retried
  /// from the last equilibrium at half the size, at most this many times in a row.
  int max_step_halvings = 8;
};

struct Recording {
  std::string path;  ///< empty = no recording (a --record flag may still ask for one)
  bool poses = true;
  bool forces = true;
  bool contacts = true;
  bool timings = true;
  bool events = true;
};

/// Trainee feedback of palpation runs (docs/scenes.md).
struct Feedback {
  double safe_force = 0.0;  ///< [N]; pressing harder is reported; 0 = no limit
};

// ---------------------------------------------------------------------------------------

/// [lod]: the haptic loop's choice among impostor levels (seed 000 §4.2).
struct LevelSelection {
  /// The share of each haptic frame the touchable objects' queries may take [s]: their
  /// levels' summed cost stays within it.
  double haptic_budget = 15e-6;
  /// Objects nearer the tool than this are worth a finer level (the benefit falls linearly
  /// from 1 in contact to 0 here); farther ones are not queried at all [m].
  double influence_radius = 0.05;
  double blend_time = 0.005;  ///< [s] the force moves from the old level's to the new one's
  /// false: every object at its finest level, never switched (what the selection saves is
  /// measured against this).
  bool select = true;
  /// Where impostor hierarchies are cached, keyed by the mesh's hash (empty: built at load).
  std::filesystem::path cache;
};

struct Model {
  std::string name;
  std::string description;
  std::string source;  ///< the file (or built-in name) it was loaded from
  Vec3 gravity = Vec3(0, 0, -9.81);  ///< [m/s²]
  LoopRates rates;
  RealtimeSettings realtime;
  std::vector<Material> materials;
  std::vector<Body> bodies;      ///< in file order
  std::vector<Device> devices;
  std::vector<Tool> tools;
  std::vector<Algorithm> algorithms;
  Recording recording;
  Feedback feedback;
  StaticSolve static_solve;
  /// [precompute]: the configuration space `tactus precompute` builds (absent: none).
  std::optional<precompute::SpaceSettings> precompute;
  /// [precompute] `tools` of a two-point space: the tools (indices into `tools`) at its first
  /// and second point, which `tactus run --space` names as the cspace body's `tools`.
  std::vector<std::size_t> precompute_tools;
  /// [lod]: how the haptic loop chooses among the bodies' impostor levels.
  LevelSelection level_selection;

  [[nodiscard]] const Material* find_material(std::string_view name) const;
  [[nodiscard]] const Body* find_body(std::string_view name) const;
  [[nodiscard]] const Device* find_device(std::string_view name) const;
  [[nodiscard]] const Tool* find_tool(std::string_view name) const;
  [[nodiscard]] const Algorithm* find_algorithm(std::string_view name) const;
};

using ModelPtr = std::shared_ptr<const Model>;

// Names as written in scene files (the inverse of what the loader accepts).
/// The material's `model` key: its FEM law, or "mass_spring".
std::string_view model_name(const Material& m);
const char* to_string(ViscoelasticModel m);
const char* to_string(BodyKind k);
const char* to_string(physics::Integrator i);
const char* to_string(physics::LinearSolver s);
const char* to_string(MassMatrix m);
const char* to_string(MappedRole r);
const char* to_string(SpringType s);
const char* tool_type_name(const ToolShape& s);
const char* device_type_name(const DeviceSource& s);
const char* trajectory_type_name(const Trajectory& t);
const char* algorithm_type_name(const AlgorithmParams& p);

}  // namespace tactus::scene
