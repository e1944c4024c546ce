#pragma once
// Forces and shapes between grid points, at haptic rate: queries allocate nothing and touch
// at most 32 grid points (the cell's 8 corners and the 24 points beyond its faces).
//  - trilinear: over the cell's corners;
//  - rbf_cubic, rbf_thin_plate: radial basis functions phi(r) = r^3 or r^2 log r over the
//    32 points, with a linear polynomial term; interpolating (exact at grid points);
//  - polynomial: a least-squares quadratic over the 32 points (smoothing, not interpolating).
// Points that are not solved are left out; where too few remain the query falls back to
// trilinear over the solved corners, and where none is solved it reports no value.
#include <array>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "precompute/settings.hpp"
#include "precompute/space.hpp"

namespace tactus::precompute {

struct Query {
  Vec3 force = Vec3::Zero();  ///< force the body exerts on the tool [N]
  bool valid = false;         ///< false: no solved point near p
  bool outside = false;       ///< p lay outside the grid and was clamped onto its box
  bool fallback = false;      ///< the method lacked points and trilinear was used
};

class Interpolator {
 public:
  static constexpr int kStencil = 32;

  Interpolator(std::shared_ptr<const Space> space, Interpolation method);

  /// The force at interaction point p [m]. Allocation-free.
  [[nodiscard]] Query force(const Vec3& p) const noexcept;
  /// The force and the nodal displacements (3N) at p. `displacement` is resized only when its
  /// size differs (size it once: then this allocates nothing either).
  Query shape(const Vec3& p, VecX& displacement) const;

  [[nodiscard]] Interpolation method() const { return method_; }
  [[nodiscard]] const Space& space() const { return *space_; }

 private:
  struct Weights {
    std::array<std::int64_t, kStencil> point{};
    std::array<double, kStencil> weight{};
    int count = 0;
    Query query;
  };
  void weights(const Vec3& p, Weights& out) const noexcept;
  bool trilinear(const std::array<int, 3>& cell, const Vec3& t, Weights& out) const noexcept;
  bool scattered(const std::array<int, 3>& cell, const Vec3& t, Weights& out) const noexcept;
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
};

}  // namespace tactus::precompute
