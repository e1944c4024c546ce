#pragma once
// Woven fabric as particles on a triangle mesh (seed 002 §III-B): each triangle knows its
// rest warp/weft (u, v) coordinates, and the fabric's measured curves give its forces.
//
// - Stretch, warp and weft apart: (W_u W_v) = (x1 − x0, x2 − x0)·(uv1 − uv0, uv2 − uv0)⁻¹, the
//   strains ‖W_u‖ − 1 and ‖W_v‖ − 1 constant over the triangle; the tension per unit width
//   T(ε) [N/m] from the warp or weft curve, energy A·∫T dε.
// - Shear: the angle γ = asin(Ŵ_u·Ŵ_v) by which warp and weft leave the right angle; the
//   shear force per unit width from the shear curve, energy A·∫T_s dγ.
// - Bending along each interior edge: the normal curvature across it, K = (2/σ)·cos(Θ/2)
//   with Θ the angle between the two triangles (π when flat) and σ the mean of the two
//   opposite vertices' heights over the edge. That is the curvature of the circle through
//   the two opposite vertices and the edge; the seed calls σ the "mean distance", so its
//   formula holds as printed (with σ the summed heights it would be half the curvature).
//   Energy A_e·∫M dK, M [N·m/m] the moment per unit width from the bending curves (warp and
//   weft mixed by the edge's direction), A_e the two triangles' area. The seed puts the
//   force F_b = M/l on the two opposite vertices only; alone it would push the fabric's
//   centre of mass, so the edge's vertices take the reaction (the energy's gradient does it:
//   the opposite vertices still get |e|·M/h, the seed's M/l with l the yarn's length h).
//   Or, where the mesh follows the yarns (a warp/weft grid), bending along the yarns: three
//   consecutive nodes a, b, c of a warp or weft line, K = |a − 2b + c|/σ², the same circle
//   through three points (σ the rest spacing), so K = (2/σ)·cos(Θ/2) with Θ the angle at b.
//   The fold of a triangle edge mixes the twist of the surface into its curvature wherever
//   the two opposite vertices do not face each other across the edge, as on every grid of
//   right triangles: there a cantilever strip bends 25–40 % too far and refining does not
//   cure it (docs/validation-fabric.md). Along the yarns K holds no twist, its Hessian is
//   exact and constant in direction, and the strip converges to the elastica.
// - Shear hysteresis (optional, KES 2HG and 2HG5): a friction element beside the shear curve,
//   per triangle a stick angle γ_s (the internal variable) and the force per unit width
//   clamp(k_h·(γ − γ_s), ±H); where it saturates, γ_s follows γ at the end of each step. Once
//   slipped, shearing forward and back runs ±H off the curve: a loop 2H wide. H grows with
//   the shear, linearly in |γ_s| through KES's widths at 0.5° (2HG) and 5° (2HG5), as the
//   yarns' crossings press harder; k_h = H/γ_y keeps the stick reach γ_y fixed.
// - Damping per term along the term's own direction (§III-B2d): force −β·k·g(g·v), g the
//   term's gradient and k its tangent stiffness, with one time constant β per kind.
// - Lumped masses: areal density × area / 3 per vertex.
#include <memory>
#include <utility>
#include <vector>

#include "mesh/tri_mesh.hpp"
#include "physics/cloth/measured_curve.hpp"
#include "physics/force_model.hpp"

namespace tactus::physics {

struct ClothMaterial {
  MeasuredCurve warp, weft;            ///< tension per unit width [N/m] against strain
  MeasuredCurve shear;                 ///< shear force per unit width [N/m] against angle [rad]
  MeasuredCurve bend_warp, bend_weft;  ///< moment per unit width [N·m/m] against curvature [1/m]
  double areal_density = 0.0;          ///< [kg/m²]
  /// Damping time constants [s] of stretch, shear and bending (damping = β × tangent stiffness
  /// of the curves; the shear friction is not damped).
  double stretch_damping = 0.0, shear_damping = 0.0, bend_damping = 0.0;
  /// Shear friction H [N/m] at 0.5°, half the width of the shear loop there (KES 2HG / 2);
  /// 0: none.
  double shear_friction = 0.0;
  /// H at 5° (KES 2HG5 / 2); 0: the same as at 0.5°. H is linear in the shear between the
  /// two, and beyond (never below 0).
  double shear_friction_5 = 0.0;
  /// The shear change [rad] over which the friction goes from sticking to slipping (its
  /// stiffness is H over it): small against the ±8° of the KES test and the 0.5° where it
  /// reads 2HG, large enough for the implicit step's tangent.
  double shear_stick_angle = 0.1 * 3.14159265358979323846 / 180.0;
};

/// Bending along a yarn: consecutive nodes a, b, c of a warp or weft line, straight and
/// equally spaced at rest, standing for `area` of fabric.
struct YarnBend {
  std::int32_t a = 0, b = 0, c = 0;
  bool warp = true;
  double area = 0.0;  ///< [m²]
  /// 2 where b is the edge of a clamp that holds the fabric level and a is held: the free side
  /// mirrored across the clamp is the true neighbour, so the curvature is twice what the held
  /// node gives (the ghost node of a clamped boundary), over the free half of the area.
  double curvature_scale = 1.0;
};

/// A mesh with its rest warp/weft coordinates (one (u, v) per vertex, in metres of fabric),
/// and the yarn lines that bend (none: every interior edge bends as a hinge).
struct ClothMesh {
  mesh::TriMesh mesh;
  std::vector<Vec2> uv;
  std::vector<YarnBend> yarns;
};

/// One interior edge: e0 → e1, o0 opposite in the triangle on its left, o1 in the other.
struct ClothHinge {
  std::int32_t e0 = 0, e1 = 0, o0 = 0, o1 = 0;
  double area = 0.0;         ///< the two triangles' rest area [m²]
  double mean_height = 0.0;  ///< σ, rest [m]
  double warp_share = 0.0;   ///< cos² of the angle between the fold's normal and the warp
  double rest_curvature = 0.0;
};

class ClothModel final : public ForceModel {
 public:
  /// Throws InputError for a non-manifold or inconsistently oriented mesh (naming the edge or
  /// the triangle), a triangle of zero (u, v) area, uv of the wrong size, a density that is
  /// not positive, or a negative damping.
  ClothModel(const ClothMesh& cloth, ClothMaterial material);

  [[nodiscard]] const ClothMaterial& material() const { return material_; }
  [[nodiscard]] const std::vector<mesh::Triangle>& triangles() const { return triangles_; }
  [[nodiscard]] const std::vector<ClothHinge>& hinges() const { return hinges_; }
  /// The warp and weft strains and the shear angle [rad] of triangle t at x.
  [[nodiscard]] Vec3 triangle_strain(const VecX& x, std::size_t t) const;
  /// The curvature across hinge h at x [1/m] (signed).
  [[nodiscard]] double hinge_curvature(const VecX& x, std::size_t h) const;
  [[nodiscard]] const std::vector<YarnBend>& yarns() const { return yarns_; }
  /// The curvature of yarn bend y at x [1/m] (≥ 0).
  [[nodiscard]] double yarn_curvature(const VecX& x, std::size_t y) const;

  // ForceModel
  [[nodiscard]] std::size_t node_count() const override { return static_cast<std::size_t>(rest_.size() / 3); }
  [[nodiscard]] const VecX& rest_positions() const override { return rest_; }
  [[nodiscard]] const VecX& lumped_mass() const override { return mass_; }
  [[nodiscard]] std::unique_ptr<Scratch> make_scratch() const override;
  /// One stick angle per triangle where the fabric has shear friction.
  [[nodiscard]] std::size_t internal_size() const override {
    return material_.shear_friction > 0.0 ? triangles_.size() : 0;
  }
  void forces(const VecX& x, const VecX& v, const VecX& q, VecX& f, Scratch& s) const override;
  void linearize(const VecX& x, const VecX& v, const VecX& q, Scratch& s) const override;
  /// The force and the linearization in one pass over the elements, then K·dx.
  void linearized_forces(const VecX& x, const VecX& v, const VecX& q, const VecX& dx, VecX& f,
                         Scratch& s) const override;
  void add_stiffness_product(const VecX& dx, VecX& out, const Scratch& s) const override;
  void add_damping_product(const VecX& dv, VecX& out, const Scratch& s) const override;
  void add_diagonal(double a, double b, VecX& out, const Scratch& s) const override;
  const BlockMatrix* assemble_system(double a, double b, double c, Scratch& s) const override;
  void add_triplets(double a, double b, std::vector<Triplet>& out, const Scratch& s) const override;
  bool add_matrix_values(double a, double b, double mass, std::span<const std::int32_t> slots, double* values,
                         const Scratch& s) const override;
  /// The stick angles follow the shear angles where the friction slips.
  void update_internal(const VecX& x, double dt, VecX& q, Scratch& s) const override;
  /// The curves' energy, and the friction's while it sticks (beyond, the convex potential
  /// whose slope is ±H: the force at fixed stick angles is its gradient).
  [[nodiscard]] double elastic_energy(const VecX& x, const VecX& q) const override;
  /// The shear friction's force per unit width [N/m] at shear angle γ with stick angle γ_s.
  [[nodiscard]] double shear_friction_force(double gamma, double stick) const;
  /// Its strength H [N/m] at stick angle γ_s.
  [[nodiscard]] double shear_friction_limit(double stick) const;

  /// A triangle's constant part: W_u = Σ a_n x_n, W_v = Σ b_n x_n.
  struct TriangleRest {
    double a[3], b[3];
    double area;
  };

 private:
  /// A triangle's warp and weft vectors W_u, W_v at x.
  [[nodiscard]] std::pair<Vec3, Vec3> warp_weft(const VecX& x, std::size_t t) const;
  /// emit(i, j, block) for each 3×3 block of add_triplets(a, b), in its order (every element
  /// emits its blocks, zero or not, so the pattern never changes).
  template <class Emit>
  void emit_blocks(double a, double b, const Scratch& s, Emit&& emit) const;
  template <bool Linearize>
  void evaluate(const VecX& x, const VecX& v, const VecX& q, VecX* f, Scratch& s) const;
  /// Triangle t's stick angle in q (0 where q holds none).
  [[nodiscard]] double stick_angle(const VecX& q, std::size_t t) const {
    const bool held = internal_size() > 0 && static_cast<std::size_t>(q.size()) == internal_size();
    return held ? q[static_cast<Eigen::Index>(t)] : 0.0;
  }

  VecX rest_, mass_;
  ClothMaterial material_;
  std::vector<mesh::Triangle> triangles_;
  std::vector<TriangleRest> rest_triangles_;
  std::vector<ClothHinge> hinges_;
  std::vector<YarnBend> yarns_;
  std::vector<double> yarn_curvature_scale_;  ///< per yarn bend σ²/curvature_scale: K = |a − 2b + c| / it
  // The assembled system's block pattern: per node its upper neighbours, and per element
  // pair its block (≥ 0: stored as (row, column); < 0: −1 − index, stored transposed).
  std::vector<std::int32_t> row_start_, column_;
  std::vector<std::int32_t> triangle_slot_;  // 3 per triangle: pairs (0,1) (0,2) (1,2)
  std::vector<std::int32_t> hinge_slot_;     // 6 per hinge: pairs of (e0, e1, o0, o1)
  std::vector<std::int32_t> yarn_slot_;      // 3 per yarn bend: pairs (a,b) (a,c) (b,c)
};

}  // namespace tactus::physics
