#pragma once
// A body rendered from a precomputed configuration space (scene kind = "cspace"): the haptic
// loop reads the force at the tool's interaction point from the space's Interpolator, and
// the simulation loop publishes the interpolated shape instead of simulating the body.
#include <cstddef>
#include <memory>

#include "core/math.hpp"
#include "precompute/interpolator.hpp"
#include "scene/model.hpp"

namespace tactus::runtime {

struct CspaceForce {
  Vec3 force = Vec3::Zero();  ///< force the body exerts on the tool [N]
  bool touching = false;      ///< the point lies in the space's grid box and has a value
};

class CspaceBody {
 public:
  /// Loads the space of scene body `index` (its kind = "cspace") and checks that it was built
  /// for this body: throws InputError, located at the space file, for another mesh, material,
  /// fixed region or a missing or malformed file.
  static std::shared_ptr<const CspaceBody> load(const scene::Model& model, std::size_t index);

  /// The force at interaction point p [m]. Outside the grid's box the tool is not attached
  /// and feels nothing. Allocation-free.
  [[nodiscard]] CspaceForce force(const Vec3& p) const noexcept;
  /// Node positions (3N) of the configuration at p: rest + interpolated displacement; the
  /// rest shape where the space has no value. Allocates only when x has another size.
  void positions(const Vec3& p, VecX& x) const;

  [[nodiscard]] std::size_t body() const { return body_; }
  [[nodiscard]] const precompute::Interpolator& interpolator() const { return interpolator_; }

  CspaceBody(std::size_t body, std::shared_ptr<const precompute::Space> space, precompute::Interpolation method);

 private:
  std::size_t body_;
  precompute::Interpolator interpolator_;
};

}  // namespace tactus::runtime
