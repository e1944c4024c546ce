#pragma once
// The proxy's surface questions answered by a triangle BVH: the accelerated counterpart of
// BruteForceSurfaceQuery for deforming meshes of thousands of triangles and more, with the
// same answers (see docs/proxy.md).
#include <array>
#include <cstdint>
#include <optional>

#include "contact/bvh.hpp"
#include "contact/surface_query.hpp"
#include "core/math.hpp"

namespace tactus::contact {

/// SurfaceQuery over a TriangleBvh: the surface as of the tree's last build or refit (refit
/// the tree after each simulation step, then query). Every answer equals
/// BruteForceSurfaceQuery's over the same positions. Nothing allocates and nothing throws:
/// a non-finite query point or a negative or NaN radius finds nothing. The tree must outlive
/// the query; several threads may query one tree while nobody refits it.
class BvhSurfaceQuery final : public SurfaceQuery {
 public:
  explicit BvhSurfaceQuery(const TriangleBvh& tree) : tree_(&tree) {}

  [[nodiscard]] ClosestSurfacePoint closest_point(const Vec3& p) const override {
    if (!p.allFinite()) return {};
    return tree_->closest_point_with_side(p);
  }

  [[nodiscard]] SweepHit sweep_sphere(const Vec3& from, const Vec3& to, double radius) const override {
    if (!from.allFinite() || !to.allFinite() || !(radius >= 0.0)) return {};
    return tree_->sweep_sphere(from, to, radius);
  }

  [[nodiscard]] std::optional<std::array<Vec3, 3>> triangle(std::int32_t t) const override {
    return tree_->triangle_corners(t);
  }

  [[nodiscard]] const TriangleBvh& tree() const { return *tree_; }

 private:
  const TriangleBvh* tree_;
};

}  // namespace tactus::contact
