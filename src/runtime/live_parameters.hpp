#pragma once
// Parameters edited while a run goes on (the viewer's panel, docs/viewer.md): the bodies'
// Young's modulus and damping, and the haptic properties of each device's contact (coupling
// stiffness, friction), and the emergency stop. One writer thread (the window) stores them
// through SeqLocks; the simulation loop reads the materials at each step and each haptic
// loop its device's surface at each frame, without a lock or an allocation.
//
// An edit carries the time from which it applies (`from`, simulated seconds): the window
// uses 0 (at once), tests schedule an edit at a given instant of a lockstep run.
//
// How an edit acts (the cheapest honest way, no rebuild of the body):
//  - Young's modulus E': the body's whole internal force model is scaled by s = E'/E
//    (forces, K, D, elastic energy). Every constitutive law of the project is linear in its
//    moduli at a fixed Poisson ratio (linear, corotational, StVK, neo-Hookean, the spring
//    networks, the Prony / standard-linear-solid arms, stiffness-proportional damping), so
//    this is the body the scene would build with E'. Mass-proportional damping does not
//    scale with E: it is put back (see below).
//  - damping α' [1/s]: the mass-proportional damping, force −α'·M·v with the lumped mass,
//    replaces the scene's (FEM: Rayleigh α; spring networks: their nodal damping expressed
//    per unit mass). Exact for lumped masses; with a consistent mass matrix the scene's
//    Rayleigh-α term used that matrix and is replaced by its lumped form.
//  - surface: the coupling stiffness of the proxy or of the penalty plane and the proxy's
//    friction coefficients, taken in the next frame; the stiffness is kept at or below the
//    device's max_stiffness, as when the scene sets it.
#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

#include "core/seqlock.hpp"
#include "haptics/haptic_step.hpp"
#include "physics/force_model.hpp"
#include "scene/model.hpp"

namespace tactus::runtime {


class LiveParameters {
 public:
  static constexpr std::size_t kMaxBodies = 8;
  static constexpr std::size_t kMaxDevices = 4;

  struct Material {
    double young_modulus = 0.0;  ///< [Pa]; 0 = not editable (rigid, cspace, no material)
    double damping = 0.0;        ///< mass-proportional α [1/s]
    bool damping_set = false;    ///< false: the scene's own damping is kept
  };
  struct Materials {
    std::uint64_t version = 0;  ///< 0 = the scene's values
    double from = 0.0;          ///< [s] simulated time from which they apply
    std::array<Material, kMaxBodies> body{};
  };
  /// What a device's contact lets edit.
  enum class SurfaceKind : std::uint8_t { none, proxy, penalty };
  struct Surface {
    std::uint64_t version = 0;
    double from = 0.0;
    double stiffness = 0.0;         ///< [N/m]
    double static_friction = 0.0;   ///< μs (proxy only)
    double kinetic_friction = 0.0;  ///< μk ≤ μs (proxy only)
  };

  /// The scene's values: materials from the model; surfaces once the run's loops are built.
  explicit LiveParameters(const scene::Model& model);
  LiveParameters(const LiveParameters&) = delete;
  LiveParameters& operator=(const LiveParameters&) = delete;

  // --- the writer (one thread) -----------------------------------------------------------
  /// Throws InputError for a body that cannot be edited or a value out of range (E > 0,
  /// α ≥ 0; a negative damping keeps the scene's).
  void set_material(std::size_t body, double young_modulus, double damping, double from = 0.0);
  /// Throws InputError for a device whose contact cannot be edited, a stiffness outside
  /// (0, max_stiffness] or friction with μk > μs or negative.
  void set_surface(std::size_t device, double stiffness, double static_friction, double kinetic_friction,
                   double from = 0.0);
  /// The values last set (the writer's own view), for the panel.
  [[nodiscard]] const Materials& edited_materials() const { return edited_materials_; }
  [[nodiscard]] const Surface& edited_surface(std::size_t device) const { return edited_surfaces_.at(device); }

  // --- scene values ----------------------------------------------------------------------
  [[nodiscard]] const Materials& scene_materials() const { return scene_materials_; }
  [[nodiscard]] bool material_editable(std::size_t body) const {
    return body < kMaxBodies && scene_materials_.body[body].young_modulus > 0.0;
  }
  /// Whether the run's loops have described their devices (the surfaces below are known).
  [[nodiscard]] bool surfaces_known() const { return surfaces_known_.load(std::memory_order_acquire); }
  [[nodiscard]] SurfaceKind surface_kind(std::size_t device) const {
    return device < kMaxDevices && surfaces_known() ? surface_kinds_[device] : SurfaceKind::none;
  }
  [[nodiscard]] const Surface& scene_surface(std::size_t device) const { return scene_surfaces_.at(device); }
  /// device < kMaxDevices (unchecked: the haptic loops read it).
  [[nodiscard]] double max_stiffness(std::size_t device) const { return max_stiffness_[device]; }

  // --- the run (before its loops start) --------------------------------------------------
  /// Records device `device`'s contact as the scene built it. Called by build_loops.
  void describe_device(std::size_t device, const haptics::HapticModel& model, double max_stiffness);
  /// Every device described: the panel may show the surfaces.
  void devices_described() { surfaces_known_.store(true, std::memory_order_release); }

  /// Any thread: every device's haptic loop stops its force at its next frame and keeps it
  /// stopped (the safety layer's emergency stop, as SessionOptions::emergency_stop_at).
  void request_emergency_stop() { emergency_stop_.store(true, std::memory_order_relaxed); }
  [[nodiscard]] bool emergency_stop_requested() const { return emergency_stop_.load(std::memory_order_relaxed); }

  // --- the readers (any thread) ----------------------------------------------------------
  [[nodiscard]] Materials materials() const { return materials_.load(); }
  /// device < kMaxDevices (unchecked: the haptic loops read it).
  [[nodiscard]] Surface surface(std::size_t device) const { return surfaces_[device].load(); }

 private:
  std::string scene_source_;
  std::size_t body_count_ = 0, device_count_ = 0;
  std::array<std::string, kMaxBodies> body_names_;
  Materials scene_materials_, edited_materials_;
  SeqLock<Materials> materials_;
  std::array<Surface, kMaxDevices> scene_surfaces_{}, edited_surfaces_{};
  std::array<SurfaceKind, kMaxDevices> surface_kinds_{};
  std::array<double, kMaxDevices> max_stiffness_{};
  std::array<SeqLock<Surface>, kMaxDevices> surfaces_;
  std::atomic<bool> surfaces_known_{false};
  std::atomic<bool> emergency_stop_{false};
};

/// The mass-proportional damping of scene body `index` per degree of freedom [1/s] (3N),
/// as the runtime builds the body (compile/bodies.cpp): FEM Rayleigh α; tetrahedral springs
/// α plus the nodal damping over the mean node mass; surface springs the nodal damping over
/// each node's lumped mass.
VecX scene_mass_damping(const scene::Model& model, std::size_t index, const VecX& lumped_mass);

/// A body's force model under live edits: the scene's model scaled by s = E'/E, with the
/// mass-proportional damping replaced (live_parameters.hpp says why this is the body with
/// the new values). set() is called by the simulation loop between steps only.
class LiveMaterialModel final : public physics::ForceModel {
 public:
  LiveMaterialModel(std::shared_ptr<const physics::ForceModel> inner, VecX scene_damping);

  /// scale = E'/E; damping < 0 keeps the scene's mass-proportional damping. Allocates nothing.
  void set(double scale, double damping);
  [[nodiscard]] double scale() const { return scale_; }

  [[nodiscard]] std::size_t node_count() const override { return inner_->node_count(); }
  [[nodiscard]] const VecX& rest_positions() const override { return inner_->rest_positions(); }
  [[nodiscard]] const VecX& lumped_mass() const override { return inner_->lumped_mass(); }
  [[nodiscard]] bool mass_is_diagonal() const override { return inner_->mass_is_diagonal(); }
  void add_mass_product(double scale, const VecX& in, VecX& out) const override { inner_->add_mass_product(scale, in, out); }
  void add_mass_triplets(double scale, std::vector<physics::Triplet>& out) const override {
    inner_->add_mass_triplets(scale, out);
  }
  [[nodiscard]] std::size_t internal_size() const override { return inner_->internal_size(); }
  [[nodiscard]] std::unique_ptr<physics::Scratch> make_scratch() const override;
  void forces(const VecX& x, const VecX& v, const VecX& q, VecX& f, physics::Scratch& s) const override;
  void linearize(const VecX& x, const VecX& v, const VecX& q, physics::Scratch& s) const override;
  void add_stiffness_product(const VecX& dx, VecX& out, const physics::Scratch& s) const override;
  void add_damping_product(const VecX& dv, VecX& out, const physics::Scratch& s) const override;
  void add_system_product(double a_mass, double b_damping, double c_stiffness, const VecX& in, VecX& out,
                          const physics::Scratch& s) const override;
  void add_diagonal(double a, double b, VecX& out, const physics::Scratch& s) const override;
  const physics::BlockMatrix* assemble_system(double a, double b, double c, physics::Scratch& s) const override;
  void linearized_forces(const VecX& x, const VecX& v, const VecX& q, const VecX& dx, VecX& f,
                         physics::Scratch& s) const override;
  void add_triplets(double a, double b, std::vector<physics::Triplet>& out, const physics::Scratch& s) const override;
  /// The scene model's values, where no added damping follows its triplets.
  bool add_matrix_values(double a, double b, double mass, std::span<const std::int32_t> slots, double* values,
                         const physics::Scratch& s) const override;
  void update_internal(const VecX& x, double dt, VecX& q, physics::Scratch& s) const override;
  [[nodiscard]] double elastic_energy(const VecX& x, const VecX& q) const override;

 private:
  std::shared_ptr<const physics::ForceModel> inner_;
  VecX scene_damping_;  ///< per dof [1/s]
  VecX extra_;          ///< added D per dof: (α' − s·α_scene)·m [N·s/m]
  bool has_extra_ = false;
  double scale_ = 1.0;
};

}  // namespace tactus::runtime
