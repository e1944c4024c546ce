#include "runtime/cspace_body.hpp"

#include <fmt/format.h>

#include "core/error.hpp"
#include "precompute/model_identity.hpp"
#include "precompute/space_file.hpp"
#include "runtime/bodies.hpp"

namespace tactus::runtime {

std::shared_ptr<const CspaceBody> CspaceBody::load(const scene::Model& model, std::size_t index) {
  const scene::Body& b = model.bodies.at(index);
  if (!b.cspace) throw InputError(fmt::format("body '{}' is not a cspace body", b.name));
  const auto& file = b.cspace->file;
  auto space = std::make_shared<precompute::Space>(precompute::read_space(file));
  // The identity of this scene's body with the settings the space was built with: a space of
  // another mesh, material or fixed region, or a mesh edited since, is refused here.
  const physics::Body body = make_physics_body(model, index);
  if (space->identity.node_count != body.model->node_count())
    throw InputError(SourceLocation{file.string(), {}, {}, {}},
                     fmt::format("the space was built for a mesh of {} nodes; body '{}' has {}",
                                 space->identity.node_count, b.name, body.model->node_count()));
  precompute::check_identity(space->identity, precompute::identify(body, space->settings, space->grid),
                             file.string());
  return std::make_shared<CspaceBody>(index, std::move(space), b.cspace->interpolation);
}

CspaceBody::CspaceBody(std::size_t body, std::shared_ptr<const precompute::Space> space,
                       precompute::Interpolation method)
    : body_(body), interpolator_(std::move(space), method) {}

CspaceForce CspaceBody::force(const Vec3& p) const noexcept {
  const precompute::Query q = interpolator_.force(p);
  CspaceForce out;
  if (q.valid && !q.outside && q.force.allFinite()) {
    out.force = q.force;
    out.touching = true;
  }
  return out;
}

void CspaceBody::positions(const Vec3& p, VecX& x) const {
  const precompute::Query q = interpolator_.shape(p, x);
  if (!q.valid || !x.allFinite()) x.setZero();
  x += interpolator_.space().rest_positions;
}

}  // namespace tactus::runtime
