#pragma once
// Linear tetrahedral (P1) finite elements as a ForceModel: one material, or one per region,
// lumped or consistent mass, Rayleigh damping and optional Prony relaxation.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "mesh/tet_mesh.hpp"
#include "physics/fem/constitutive.hpp"
#include "physics/fem/material.hpp"
#include "physics/force_model.hpp"

namespace tactus::physics {

/// Rest data of one element, precomputed once.
struct TetElement {
  std::array<std::int32_t, 4> nodes{};
  Eigen::Matrix<double, 3, 4> grad;   ///< shape-function gradients g_a = grad N_a (columns)
  Eigen::Matrix<double, 3, 4> sgrad;  ///< sqrt(volume) * grad, for the stiffness kernel
  double volume = 0.0;                ///< rest volume [m^3]
  std::int32_t material = 0;          ///< index into the body's materials (its region's)
};

/// Lumped: ρV/4 on each node of an element. Consistent: the P1 mass matrix
/// M_e = ρV/20 (1 + δ_ab) I3 over the element's node pairs (a, b).
enum class FemMass { lumped, consistent };

class TetFem final : public ForceModel {
 public:
  /// Throws InputError for an invalid material, an out-of-range node index, or an inverted
  /// or zero-volume rest element (named by its index).
  TetFem(const mesh::TetMesh& mesh, const FemMaterial& material, FemMass mass = FemMass::lumped);
  /// Regions of one body: element t takes materials[element_material[t]] (all the first when
  /// element_material is empty). The materials share the law, damping, relaxation and tangent
  /// projection and differ in elastic constants and density; InputError otherwise, or for an
  /// index out of range.
  TetFem(const mesh::TetMesh& mesh, std::span<const FemMaterial> materials,
         std::span<const std::int32_t> element_material, FemMass mass = FemMass::lumped);

  [[nodiscard]] std::size_t node_count() const override { return static_cast<std::size_t>(rest_.size() / 3); }
  [[nodiscard]] const VecX& rest_positions() const override { return rest_; }
  [[nodiscard]] const VecX& lumped_mass() const override { return mass_; }
  [[nodiscard]] bool mass_is_diagonal() const override { return mass_kind_ == FemMass::lumped; }
  void add_mass_product(double scale, const VecX& in, VecX& out) const override;
  void add_mass_triplets(double scale, std::vector<Triplet>& out) const override;
  [[nodiscard]] FemMass mass_kind() const { return mass_kind_; }
  [[nodiscard]] std::size_t internal_size() const override { return elements_.size() * q_stride_; }
  [[nodiscard]] std::unique_ptr<Scratch> make_scratch() const override;

  void forces(const VecX& x, const VecX& v, const VecX& q, VecX& f, Scratch& s) const override;
  void linearize(const VecX& x, const VecX& v, const VecX& q, Scratch& s) const override;
  bool linearize_exact(const VecX& x, const VecX& v, const VecX& q, Scratch& s) const override;
  /// Linear: K0. Corotational: R K0 R^T per element (the usual corotational stiffness,
  /// without the derivative of R). Hyperelastic: the (projected) tangent at the linearization.
  void add_stiffness_product(const VecX& dx, VecX& out, const Scratch& s) const override;
  /// D = alpha M + beta R K0 R^T (R = I for the linear law, M the body's mass matrix): Rayleigh damping on the rotated
  /// rest stiffness, positive semi-definite for every law and state.
  void add_damping_product(const VecX& dv, VecX& out, const Scratch& s) const override;
  /// One element pass: with D = alpha M + beta K_rest, a·M + b·D + c·K is
  /// (a + b alpha) M + (b beta + c) K_rest for the linear and corotational laws.
  void add_system_product(double a, double b, double c, const VecX& in, VecX& out, const Scratch& s) const override;
  void add_diagonal(double a, double b, VecX& out, const Scratch& s) const override;
  /// Linear and corotational laws: (a + b alpha) M + (c + b beta) R K0 R^T, element blocks
  /// summed in element order. Hyperelastic laws: nullptr (matrix-free).
  const BlockMatrix* assemble_system(double a_mass, double b_damping, double c_stiffness, Scratch& s) const override;
  /// Linear and corotational laws: the rotations, the force and the product in one element
  /// pass (the corotational force is linear in x for fixed rotations: f + K dx is the force at
  /// x - dx with the rotations of x). Hyperelastic laws: the default.
  void linearized_forces(const VecX& x, const VecX& v, const VecX& q, const VecX& dx, VecX& f,
                         Scratch& s) const override;
  void add_triplets(double a, double b, std::vector<Triplet>& out, const Scratch& s) const override;
  bool add_matrix_values(double a, double b, double mass, std::span<const std::int32_t> slots, double* values,
                         const Scratch& s) const override;
  void update_internal(const VecX& x, double dt, VecX& q, Scratch& s) const override;
  /// Elastic energy of the laws' strain energy densities (the Maxwell branches' stored
  /// energy is not included).
  [[nodiscard]] double elastic_energy(const VecX& x, const VecX& q) const override;
  /// Hyperelastic laws: min over the elements of det F. Linear and corotational laws:
  /// +infinity (their forces stay bounded through an inversion).
  [[nodiscard]] double min_volume_ratio(const VecX& x) const override;

  /// The first region's material (the law, damping and relaxation are every region's).
  [[nodiscard]] const FemMaterial& material() const { return materials_.front(); }
  /// Every region's material, in the order the elements' `material` indices count.
  [[nodiscard]] const std::vector<FemMaterial>& materials() const { return materials_; }
  [[nodiscard]] const LawParams& law() const { return laws_.front(); }
  [[nodiscard]] const std::vector<TetElement>& elements() const { return elements_; }
  /// F = sum_a x_a g_a^T of element e at positions x.
  [[nodiscard]] Mat3 deformation_gradient(const VecX& x, std::size_t e) const;

 private:
  void linearize_tangent(const VecX& x, const VecX& v, const VecX& q, Scratch& s, bool project) const;
  struct Cache;
  Cache& cache(Scratch& s) const;
  const Cache& cache(const Scratch& s) const;
  [[nodiscard]] bool rotations_current(const VecX& x, const Cache& c) const;
  /// Rotations and rotated gradients of elements [begin, end) at x.
  void update_rotations(const VecX& x, std::size_t begin, std::size_t end, Cache& c) const;
  void ensure_rotations(const VecX& x, Cache& c) const;
  template <bool Rotated, class Sink>
  void rest_stiffness_columns(const VecX& dx, double scale, std::size_t begin, std::size_t end, const Cache& c,
                              Sink sink) const;
  template <class Sink>
  void tangent_columns(const VecX& dx, double c_tangent, double b_rest, std::size_t begin, std::size_t end,
                       const Cache& c, Sink sink) const;
  /// out += mass_scale·M·in + the sum of the element contributions kernel(begin, end, sink)
  /// hands to sink(e, columns). On one thread the contributions go straight into out; on
  /// several, each element stores its own (Cache::columns) and gather() sums them per node.
  /// Either way every node adds its mass term and then its elements in element order, so
  /// the sums are the same whatever the thread count.
  template <class Kernel>
  void accumulate(const Cache& c, double mass_scale, const VecX& in, VecX& out, Kernel&& kernel) const;
  /// Adds every element's nodal columns (Cache::columns) to out, node by node in element
  /// order, plus mass_scale·M·in.
  void gather(const Cache& c, double mass_scale, const VecX& in, VecX& out) const;
  /// Builds the 9×9 tangents a deferred StVK linearization left as F and S (Cache::stvk_fs);
  /// the matrices' assembly reads them. One caller at a time per scratch, as every use of it.
  void expand_deferred_tangent(const Cache& c) const;
  void element_matrix(std::size_t e, double a, double b, const Cache& c, Eigen::Matrix<double, 12, 12>& k) const;
  /// emit(row, col, value) for each triplet of add_triplets(a, b), in its order.
  template <class Emit>
  void emit_triplets(double a, double b, const Cache& c, Emit&& emit) const;
  /// emit(row, col, value) for each triplet of add_mass_triplets(scale), in its order.
  template <class Emit>
  void emit_mass_triplets(double scale, Emit&& emit) const;
  /// The number of triplets add_triplets(a, b) appends.
  [[nodiscard]] std::size_t triplet_count(double b) const;
  [[nodiscard]] std::size_t mass_triplet_count() const;
  [[nodiscard]] bool rotated() const { return law().law != FemLaw::linear; }
  [[nodiscard]] const LawParams& law_of(const TetElement& el) const { return laws_[static_cast<std::size_t>(el.material)]; }
  [[nodiscard]] double density_of(const TetElement& el) const { return densities_[static_cast<std::size_t>(el.material)]; }
  [[nodiscard]] bool hyperelastic() const { return law().law != FemLaw::linear && law().law != FemLaw::corotational; }
  /// The share of a mass term accumulate() adds node by node: all of it for the lumped mass;
  /// none for the consistent one, which add_mass_product() adds after the element pass.
  [[nodiscard]] double nodal_mass_scale(double scale) const { return mass_kind_ == FemMass::lumped ? scale : 0.0; }
  /// out += scale·M·in for the consistent mass only (nothing for the lumped one).
  void add_consistent_mass(double scale, const VecX& in, VecX& out) const;

  std::vector<FemMaterial> materials_;  ///< per region
  std::vector<LawParams> laws_;   ///< per region
  std::vector<double> densities_; ///< per region [kg/m^3]
  FemMass mass_kind_ = FemMass::lumped;
  std::vector<TetElement> elements_;
  VecX rest_, mass_;
  /// The mass matrix's diagonal (the lumped mass, or 2/5 of it for the consistent one) and,
  /// consistent mass only, the part of M in that add_consistent_mass applies node by node.
  VecX mass_diagonal_, consistent_own_;
  std::size_t q_stride_ = 0;
  /// Node -> element columns (4 e + local index), in element order: node_slot_ from
  /// node_start_[i] to node_start_[i + 1].
  std::vector<std::int32_t> node_start_, node_slot_;
  /// The block pattern of the assembled system (BlockMatrix::row_start, column) and, per
  /// element, the upper block of each node pair (0,1), (0,2), (0,3), (1,2), (1,3), (2,3):
  /// its index, or -1 - index where the pair's first node is the later row (the element block
  /// goes in transposed).
  std::vector<std::int32_t> block_row_start_, block_column_;
  std::vector<std::array<std::int32_t, 6>> pair_block_;
  /// Upper block -> the element pairs that add to it, in element order: 6 e + pair, or
  /// -1 - (6 e + pair) where the element block goes in transposed; block k's from
  /// block_pair_start_[k] to block_pair_start_[k + 1]. Threads assembling the system row by
  /// row add each block's terms in the order the serial element loop does.
  std::vector<std::int32_t> block_pair_start_, block_pair_;
};

}  // namespace tactus::physics
