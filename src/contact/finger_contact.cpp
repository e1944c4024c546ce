#include "contact/finger_contact.hpp"

#include <cmath>

#include <fmt/format.h>

#include "core/error.hpp"

namespace tactus::contact {
namespace {

void check_friction(double mu_s, double mu_k, const char* who) {
  if (!(std::isfinite(mu_s) && mu_s >= 0.0))
    throw InputError(fmt::format("{}: static friction must be finite and not negative, got {}", who, mu_s));
  if (!(std::isfinite(mu_k) && mu_k >= 0.0 && mu_k <= mu_s))
    throw InputError(
        fmt::format("{}: kinetic friction must be finite, not negative and at most static friction {}, got {}", who,
                    mu_s, mu_k));
}

}  // namespace

FingerContact::FingerContact(const CapsuleShape& thumb, const CapsuleShape& index, const FingerContactParams& params)
    : thumb_(thumb), index_(index), params_(params), law_(params.normal_law) {
  validate(thumb, "finger contact: thumb");
  validate(index, "finger contact: index");
  if (!(std::isfinite(params.tangential_stiffness) && params.tangential_stiffness > 0.0))
    throw InputError(fmt::format("finger contact: tangential stiffness must be positive and finite, got {} N/m",
                                 params.tangential_stiffness));
  check_friction(params.static_friction, params.kinetic_friction, "finger contact");
}

FingerContactResult FingerContact::update(FingerContactState& state, const Pose& thumb_pose,
                                          const Pose& index_pose) const noexcept {
  FingerContactResult out;
  if (!finite_pose(thumb_pose) || !finite_pose(index_pose)) return out;
  Pose thumb = thumb_pose, index = index_pose;
  thumb.orientation.normalize();
  index.orientation.normalize();

  const CapsulePair pair = capsule_capsule(posed(thumb_, thumb), posed(index_, index));
  const double depth = -pair.signed_distance;
  if (!(depth > 0.0)) {
    state = FingerContactState{};
    return out;
  }
  const Vec3 n = pair.normal;
  const Vec3 c = 0.5 * (pair.on_first + pair.on_second);
  if (!state.in_contact) {
    // First touch: the two material points at the contact are tied together.
    state.in_contact = true;
    state.friction = FrictionState::stick;
    state.anchor_on_thumb = thumb.to_local(c);
    state.anchor_on_index = index.to_local(c);
  }

  const double fn = law_.force(depth);
  const double k = params_.tangential_stiffness;
  // How far the index's point has slid from the anchor, across the normal.
  const Vec3 lag = index.to_world(state.anchor_on_index) - thumb.to_world(state.anchor_on_thumb);
  Vec3 lag_t = lag - lag.dot(n) * n;
  const double mu = state.friction == FrictionState::slip ? params_.kinetic_friction : params_.static_friction;
  FrictionState friction = FrictionState::stick;
  // A relative sliver of tolerance: a finger resting on the kinetic cone does not slip on round-off.
  if (k * lag_t.norm() > mu * fn * (1.0 + 1e-9)) {
    // Slip (eq. 2 violated): re-tie at the current contact, the anchor behind it by the
    // spring length that gives F^T = μ_k·F^N.
    friction = FrictionState::slip;
    const Vec3 dir = lag_t.normalized();
    lag_t = (params_.kinetic_friction * fn / k) * dir;
    state.anchor_on_index = index.to_local(c);
    state.anchor_on_thumb = thumb.to_local(c - lag_t);
  }
  state.friction = friction;

  const Vec3 ft = -k * lag_t;  // pulls the index back toward the anchor
  out.in_contact = true;
  out.friction = friction;
  out.depth = depth;
  out.normal_force = fn;
  out.tangential_force = ft.norm();
  out.normal = n;
  out.contact_point = c;
  out.force_on_index = fn * n + ft;
  out.force_on_thumb = -out.force_on_index;
  return out;
}

}  // namespace tactus::contact
