#pragma once
// A network of point masses joined by springs (seed 000 eq. 9, seed 004 eq. 3), with
// Kelvin–Voigt dashpots, Maxwell arms (standard linear solid / Prony) per spring, nodal
// absolute damping d_i u̇_i, and three-node angle ("torsional") terms.
#include <cstdint>
#include <memory>
#include <vector>

#include "physics/force_model.hpp"
#include "physics/mass_spring/angle_term.hpp"

namespace tactus::physics {

struct Spring {
  std::int32_t i = 0, j = 0;
  double stiffness = 0.0;    ///< long-term k [N/m]
  double rest_length = 0.0;  ///< [m]
  double damping = 0.0;      ///< axial dashpot c in parallel (Kelvin–Voigt) [N·s/m]
  std::int32_t arm_begin = 0, arm_count = 0;  ///< Maxwell arms; also their internal variables
};

/// A spring k in series with a dashpot c, in parallel with its Spring. Its internal variable
/// is the dashpot's elongation.
struct SpringArm {
  double stiffness = 0.0;
  double damping = 0.0;
};

/// ½ k_θ (θ − θ0)² on the angle at node b between edges b→a and b→c.
struct AngleSpring {
  std::int32_t a = 0, b = 0, c = 0;
  double stiffness = 0.0;  ///< [N·m/rad²]
  double rest_angle = 0.0;
};

/// How the angle terms enter K. Gauss–Newton (k_θ ∇θ∇θᵀ) is PSD by construction; projected
/// clamps the exact Hessian's negative eigenvalues; exact is for derivative checks.
enum class AngleHessian { gauss_newton, projected, exact };

struct SpringNetworkOptions {
  /// Drop the transverse term T/l (I − n nᵀ) of compressed springs (T < 0) so K stays PSD.
  bool project_compressed = true;
  AngleHessian angle_hessian = AngleHessian::gauss_newton;
};

class SpringNetwork final : public ForceModel {
 public:
  /// rest: 3N positions; node_mass: N masses (> 0).
  SpringNetwork(VecX rest, const VecX& node_mass, SpringNetworkOptions options = {});

  /// Adds a spring at its rest length; returns its index. Arms may be empty.
  std::int32_t add_spring(std::int32_t i, std::int32_t j, double stiffness, double damping = 0.0,
                          const std::vector<SpringArm>& arms = {});
  /// Adds an angle term at node b, rest angle from the rest positions.
  void add_angle(std::int32_t a, std::int32_t b, std::int32_t c, double stiffness);
  /// Absolute damping d of a node (seed 000's d_i u̇_i) [N·s/m].
  void set_nodal_damping(std::int32_t node, double d);
  void set_options(const SpringNetworkOptions& options) { options_ = options; }

  /// A copy with only the springs and angles that touch a free node: the cheaper model of a
  /// body whose other nodes are fixed. Node numbering and internal variables are unchanged,
  /// so a state of this network is a state of the copy.
  [[nodiscard]] std::shared_ptr<SpringNetwork> restricted(const std::vector<std::uint8_t>& node_fixed) const;

  [[nodiscard]] const std::vector<Spring>& springs() const { return springs_; }
  [[nodiscard]] const std::vector<SpringArm>& arms() const { return arms_; }
  [[nodiscard]] const std::vector<AngleSpring>& angles() const { return angles_; }
  [[nodiscard]] const SpringNetworkOptions& options() const { return options_; }
  [[nodiscard]] double nodal_damping(std::int32_t node) const { return damping_[3 * node]; }

  // ForceModel
  [[nodiscard]] std::size_t node_count() const override { return static_cast<std::size_t>(rest_.size() / 3); }
  [[nodiscard]] const VecX& rest_positions() const override { return rest_; }
  [[nodiscard]] const VecX& lumped_mass() const override { return mass_; }
  [[nodiscard]] std::size_t internal_size() const override { return arms_.size(); }
  [[nodiscard]] std::unique_ptr<Scratch> make_scratch() const override;
  void forces(const VecX& x, const VecX& v, const VecX& q, VecX& f, Scratch& s) const override;
  void linearize(const VecX& x, const VecX& v, const VecX& q, Scratch& s) const override;
  void add_stiffness_product(const VecX& dx, VecX& out, const Scratch& s) const override;
  void add_damping_product(const VecX& dv, VecX& out, const Scratch& s) const override;
  void add_diagonal(double a, double b, VecX& out, const Scratch& s) const override;
  void add_triplets(double a, double b, std::vector<Triplet>& out, const Scratch& s) const override;
  void update_internal(const VecX& x, double dt, VecX& q, Scratch& s) const override;
  [[nodiscard]] double elastic_energy(const VecX& x, const VecX& q) const override;

 private:
  void check_node(std::int32_t n) const;

  VecX rest_, mass_, damping_;  // damping_: d_i per dof (3N)
  std::vector<Spring> springs_;
  std::vector<SpringArm> arms_;
  std::vector<AngleSpring> angles_;
  SpringNetworkOptions options_;
};

}  // namespace tactus::physics
