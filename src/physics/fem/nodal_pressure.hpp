#pragma once
// Nearly incompressible hyperelasticity on linear tetrahedra without volumetric locking: the
// volume change is averaged over each node's elements (Bonet & Burton 1998, "average nodal
// pressure"). A TetFem whose law keeps only its isochoric part carries the shear; this model
// adds the volumetric energy
//
//   U = Σ_a V_a κ_a/2 (J̄_a − 1)²,   J̄_a = v_a / V_a,   v_a = Σ_{e∋a} v_e/4,   V_a = Σ_{e∋a} V_e/4,
//
// (v current, V rest volumes, κ_a the volume-weighted bulk modulus of a's elements). It is the
// mixed P1–P1 displacement–pressure formulation Π(u, p) = ∫ψ_iso + ∫p(J − 1) − ∫p²/(2κ) with
// the pressure's mass lumped at the nodes, the pressure condensed: p_a = κ_a(J̄_a − 1), and an
// element feels the mean of its nodes' pressures. A linear tet then has a quarter as many
// volume constraints as one pressure per element imposes, which is what lets it shear at
// ν → 0.5. P1–P1 does not satisfy the inf–sup condition in general: the pressure may show
// node-to-node oscillations on some meshes; the displacements are what it is used for here
// (docs/validation-fem.md, "Nodal pressure").
#include <memory>
#include <utility>
#include <vector>

#include "physics/fem/tet_fem.hpp"

namespace tactus::physics {

class NodalPressureFem final : public ForceModel {
 public:
  /// `isochoric`: a TetFem built from materials with `nodal_pressure` set (its elements carry
  /// no volumetric term); the bulk moduli come from those materials.
  explicit NodalPressureFem(std::shared_ptr<const TetFem> isochoric);

  [[nodiscard]] const TetFem& isochoric() const { return *inner_; }
  [[nodiscard]] std::size_t node_count() const override { return inner_->node_count(); }
  [[nodiscard]] const VecX& rest_positions() const override { return inner_->rest_positions(); }
  [[nodiscard]] const VecX& lumped_mass() const override { return inner_->lumped_mass(); }
  [[nodiscard]] bool mass_is_diagonal() const override { return inner_->mass_is_diagonal(); }
  void add_mass_product(double scale, const VecX& in, VecX& out) const override { inner_->add_mass_product(scale, in, out); }
  void add_mass_triplets(double scale, std::vector<Triplet>& out) const override { inner_->add_mass_triplets(scale, out); }
  [[nodiscard]] std::size_t internal_size() const override { return inner_->internal_size(); }
  [[nodiscard]] std::unique_ptr<Scratch> make_scratch() const override;

  void forces(const VecX& x, const VecX& v, const VecX& q, VecX& f, Scratch& s) const override;
  /// The isochoric part's projected tangent and the volumetric term's positive semi-definite
  /// part Σ_a κ_a/V_a g_a g_aᵀ (g_a = ∂v_a/∂x), for CG.
  void linearize(const VecX& x, const VecX& v, const VecX& q, Scratch& s) const override;
  /// The exact tangent: the isochoric part's, and the volumetric term's with its geometric
  /// part Σ_e p̄_e ∂²v_e/∂x².
  bool linearize_exact(const VecX& x, const VecX& v, const VecX& q, Scratch& s) const override;
  void add_stiffness_product(const VecX& dx, VecX& out, const Scratch& s) const override;
  void add_damping_product(const VecX& dv, VecX& out, const Scratch& s) const override;
  void add_system_product(double a, double b, double c, const VecX& in, VecX& out, const Scratch& s) const override;
  void add_diagonal(double a, double b, VecX& out, const Scratch& s) const override;
  void add_triplets(double a, double b, std::vector<Triplet>& out, const Scratch& s) const override;
  void update_internal(const VecX& x, double dt, VecX& q, Scratch& s) const override;
  [[nodiscard]] double elastic_energy(const VecX& x, const VecX& q) const override;
  [[nodiscard]] double min_volume_ratio(const VecX& x) const override { return inner_->min_volume_ratio(x); }

  /// Each node's pressure p_a = κ_a (J̄_a − 1) at x [Pa].
  [[nodiscard]] VecX nodal_pressures(const VecX& x) const;

 private:
  struct State;
  struct Work;
  /// Element volume gradients, nodal pressures and their element means at x.
  void evaluate(const VecX& x, State& s) const;
  /// out += K_vol·dx at the linearization in w (with its geometric part where exact).
  void add_volumetric_product(const VecX& dx, VecX& out, const Work& w) const;
  /// The nonzero entries of g_a = ∂v_a/∂x, node by node.
  [[nodiscard]] std::vector<std::pair<std::int32_t, Vec3>> nodal_gradient(std::int32_t a, const State& s) const;
  /// visit(a·κ_n/V_n, g_n) for each node n of positive rest volume: the terms a·κ/V g gᵀ.
  template <class Visit>
  void for_each_node_term(double a, const State& s, Visit&& visit) const;

  std::shared_ptr<const TetFem> inner_;
  VecX rest_volume_;  ///< V_a per node
  VecX kappa_;        ///< κ_a per node
  std::vector<double> sign_;  ///< per element: the sign that makes its volume formula positive at rest
  std::vector<std::vector<std::int32_t>> node_elements_;  ///< the elements around each node
};

/// The TetFem of a FEM body's model: the model itself, or the isochoric part a
/// NodalPressureFem adds to; nullptr for other models.
[[nodiscard]] const TetFem* tet_fem_of(const ForceModel* model);

}  // namespace tactus::physics
