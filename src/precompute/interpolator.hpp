#pragma once
// Forces and shapes between grid points, at haptic rate: queries allocate nothing and touch
// at most 64 grid points (the 4 × 4 × 4 block around the cell).
//  - trilinear: over the cell's corners;
//  - rbf_cubic, rbf_thin_plate: radial basis functions phi(r) = r^3 or r^2 log r over 32
//    points (the cell's 8 corners and the 24 beyond its faces), with a linear polynomial
//    term; interpolating (exact at grid points);
//  - polynomial: a least-squares quadratic over the 32 points (smoothing, not interpolating);
//  - tricubic_hermite: the tensor-product cubic Hermite over the cell's corners, from each
//    corner's value and gradient (stored with the configuration) and its mixed derivatives
//    (differences of the neighbours' gradients, central where both neighbours are solved);
//    C¹ across cells and exact for cubic polynomials where the differences are central;
//  - rbf_hermite: Hermite–Birkhoff radial basis functions, phi(r) = r^3 over the 32 points,
//    interpolating values and gradients, with a linear polynomial term.
// Points that are not solved are left out; where too few remain the query falls back to
// trilinear over the solved corners, and where none is solved it reports no value. The
// Hermite methods need a space with derivatives (version 2 files; the constructor throws
// InputError for one without).
#include <array>
#include <cstdint>
#include <memory>
#include <unordered_map>
#include <utility>
#include <vector>

#include "precompute/settings.hpp"
#include "precompute/space.hpp"

namespace tactus::precompute {

struct Query {
  Vec3 force = Vec3::Zero();  ///< force the body exerts on the tool [N]
  /// Torque the body exerts on the tool about the interaction point [N·m]: force_and_torque
  /// only, zero where the space stores none (files before version 3).
  Vec3 torque = Vec3::Zero();
  bool valid = false;         ///< false: no solved point near p
  bool outside = false;       ///< p lay outside the grid and was clamped onto its box
  bool fallback = false;      ///< the method lacked points and trilinear was used
  /// Two-point spaces: a level around the other point had no value at p, so the levels were
  /// combined trilinearly instead of triquadratically (pair.hpp).
  bool across_levels = false;
  /// Two-point spaces: a level around the other point had no value at p, and a stencil
  /// linear along one or two axes (quadratic along the rest) left it out (pair.hpp).
  bool levels_lowered = false;
};

class Interpolator {
 public:
  static constexpr int kStencil = 32;
  static constexpr int kBlock = 64;  ///< the 4 × 4 × 4 block a Hermite query may touch

  Interpolator(std::shared_ptr<const Space> space, Interpolation method);

  /// The force at interaction point p [m]. Allocation-free.
  [[nodiscard]] Query force(const Vec3& p) const noexcept;

  /// A corner's weights in the tricubic Hermite at a place in its cell: of its value, its
  /// gradient (per metre: times the spacing) and its mixed derivatives ∂xy, ∂xz, ∂yz, ∂xyz.
  struct CornerBasis {
    double value = 0.0;
    Vec3 gradient = Vec3::Zero();
    std::array<double, 4> mixed{};
  };
  /// A point located on the grid, with the Hermite weights of its cell's corners: made once
  /// for several spaces on the same grid (a two-point space's levels query each at one p).
  struct Located {
    std::array<int, 3> cell{};
    Vec3 t = Vec3::Zero();
    bool outside = false;
    std::array<CornerBasis, 8> basis{};  ///< tricubic_hermite only
  };
  [[nodiscard]] Located locate(const Vec3& p) const noexcept;
  /// force(p), bit for bit, with p located by `at` (from locate(p) on this space or one on
  /// the same grid): a grid cell whose corners are solved (tricubic Hermite) costs no basis
  /// and no search, and trilinear weights need no second search.
  [[nodiscard]] Query force(const Vec3& p, const Located& at) const noexcept;
  /// The force and the torque at p, both by the space's method (the Hermite methods from the
  /// stored ∂torque/∂x as from ∂force/∂x). Allocation-free; slower than force(p), which keeps
  /// the corners' mixed derivatives of the force evaluated.
  [[nodiscard]] Query force_and_torque(const Vec3& p) const noexcept;
  /// force_and_torque(p) with p located by `at`, as force(p, at): a grid cell whose corners
  /// are solved (tricubic Hermite) costs two Hermite sums, each as cheap as the force's.
  [[nodiscard]] Query force_and_torque(const Vec3& p, const Located& at) const noexcept;
  /// The force and the nodal displacements (3N) at p. `displacement` is resized only when its
  /// size differs (size it once: then this allocates nothing either).
  Query shape(const Vec3& p, VecX& displacement) const;

  [[nodiscard]] Interpolation method() const { return method_; }
  /// How far the tricubic Hermite force at the cell's centre lies from the mean of its
  /// corners' forces, relative to the largest of them: where the force–position map bends
  /// (refinement's error indicator). Negative where the cell's corners are not all solved.
  /// tricubic_hermite only.
  [[nodiscard]] double cell_disagreement(const LatticeIndex& cell) const;
  /// The largest, over the cell's 12 edges a–b, of |f_b − f_a − ½(∂F/∂x_a + ∂F/∂x_b)(x_b − x_a)|
  /// [N]: what the stored derivatives cannot explain of the force's change along an edge. On a
  /// smooth map it is the trapezoid rule's error, of the order h³·f‴/12; where the tissue snaps
  /// (two equilibria, the force jumping within the cell) it is about the jump. Negative where
  /// the corners are not all solved. tricubic_hermite only.
  [[nodiscard]] double cell_jump(const LatticeIndex& cell) const;
  [[nodiscard]] const Space& space() const { return *space_; }

 private:
  /// The query as weights on stored data: Σ weight·value + Σ gradient·(∂/∂x, ∂/∂y, ∂/∂z)
  /// over `count` points (gradient weights in metres; zero for the non-Hermite methods).
  struct Weights {
    std::array<std::int64_t, kBlock> point{};
    std::array<double, kBlock> weight{};
    std::array<Vec3, kBlock> gradient{};
    int count = 0;
    bool with_gradients = false;
    Query query;
  };
  /// One term of a mixed derivative at a point: coeff · ∂f/∂x_axis at `point` (at `ijk` on
  /// the lattice of the level it was taken on).
  struct Term {
    std::int64_t point = 0;
    std::array<std::int32_t, 3> ijk{};
    int axis = 0;
    double coeff = 0.0;
  };
  /// A point's mixed derivatives ∂xy, ∂xz, ∂yz, ∂xyz on one level: as terms on gradients, and
  /// those of the force and of the torque evaluated.
  struct Mixed {
    std::array<std::vector<Term>, 4> terms;
    std::array<Vec3, 4> force{}, torque{};
  };
  static constexpr int kLevels = Space::kMaxLevel + 1;
  /// A cell of some level and a place in it, [0, 1]³.
  struct Place {
    LatticeIndex cell;
    Vec3 t = Vec3::Zero();
  };
  void weights(const Vec3& p, Weights& out) const noexcept;
  /// Σ weight·value + Σ gradient·(∂/∂x, ∂/∂y, ∂/∂z) over the points and weights in `w`.
  [[nodiscard]] Vec3 weighted_sum(const Weights& w, const std::vector<Vec3>& values,
                                  const std::vector<Mat3>& gradients) const noexcept;
  /// The force of the points and weights in `w`, into w.query.force.
  Query weighted_force(Weights& w) const noexcept;
  /// force(p, at), and with Torque force_and_torque(p, at).
  template <bool Torque>
  [[nodiscard]] Query located(const Vec3& p, const Located& at) const noexcept;
  bool trilinear(const std::array<int, 3>& cell, const Vec3& t, Weights& out) const noexcept;
  bool scattered(const std::array<int, 3>& cell, const Vec3& t, Weights& out) const noexcept;
  /// The cell holding p (clamped onto the grid: query.outside) and p's place in it, [0, 1]³.
  void locate(const Vec3& p, std::array<int, 3>& cell, Vec3& t, Query& query) const noexcept;
  /// From the grid's cell down through refined cells: path[0..depth], returns depth.
  int descend(const std::array<int, 3>& cell, const Vec3& t, std::array<Place, kLevels>& path) const noexcept;
  /// The cell's 8 corner points; false unless each is solved and has its mixed derivatives.
  bool corners(const LatticeIndex& cell, std::array<std::size_t, 8>& points) const noexcept;
  bool tricubic(const Place& place, Weights& out) const noexcept;
  /// The tricubic Hermite force straight from the corners' data; false unless all 8 are solved.
  bool tricubic_force(const Place& place, Vec3& force) const noexcept;
  /// The tricubic Hermite sum over a cell's 8 solved corners (points) at `level` with their
  /// weights: of the force, or with Torque of the torque.
  template <bool Torque = false>
  [[nodiscard]] Vec3 hermite_sum(const std::array<std::size_t, 8>& points, int level,
                                 const std::array<CornerBasis, 8>& basis) const noexcept;
  [[nodiscard]] const Mixed* mixed(std::size_t point, int level) const noexcept;
  [[nodiscard]] Mixed mixed_at(const LatticeIndex& at) const;
  static std::uint64_t fine_key(std::size_t point, int level) {
    return static_cast<std::uint64_t>(point) * kLevels + static_cast<std::uint64_t>(level);
  }
  /// Appends coeff times the derivative of the given orders at lattice place `at` as terms on
  /// the stored gradients of that level's points (orders summing to 1, 2 or 3).
  void mixed_terms(const LatticeIndex& at, std::array<int, 3> order, double coeff, std::vector<Term>& out) const;
  void build_tricubic();
  /// The weight matrix of a partial stencil (the stencil points used, as bits), computed the
  /// same way as full_: empty when the stencil's system is singular.
  [[nodiscard]] Eigen::MatrixXd partial_matrix(std::uint32_t used) const;

  std::shared_ptr<const Space> space_;
  Interpolation method_;
  /// Stencil offsets from the cell's lower corner, in grid units.
  std::array<std::array<int, 3>, kStencil> offsets_{};
  /// Full stencils: the weights are this matrix times the basis vector at the query point
  /// (RBF: the inverse of the interpolation matrix; polynomial: the pseudo-inverse's rows).
  Eigen::MatrixXd full_;
  /// Partial stencils (the grid's borders, next to points not solved): the weight matrix of
  /// every one that occurs in the space, by its mask, sorted, built with the interpolator. A
  /// query then costs about what a full stencil does instead of a dense solve; a mask not
  /// found (more than kMaxPartial kinds) is still solved at query time.
  static constexpr std::size_t kMaxPartial = 4096;
  std::vector<std::pair<std::uint32_t, Eigen::MatrixXd>> partial_;
  /// tricubic_hermite: the mixed derivatives of every solved grid point (level 0), and of the
  /// refined points on each level they are a corner on (by fine_key).
  std::vector<Mixed> mixed_;
  std::unordered_map<std::uint64_t, Mixed> mixed_fine_;
};

}  // namespace tactus::precompute
