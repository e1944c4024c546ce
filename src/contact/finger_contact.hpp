#pragma once
// Finger–finger contact without fabric between them (seed 002 §V-B, contact states II and
// III). The normal force is the Pawluk & Howe fingerpad law (eq. 1) on the capsules'
// penetration depth. The tangential force is a spring between two material points that
// met when the contact began, one on each finger; the one on the thumb is the anchor, kept
// in the thumb's frame (the seed watches the index move in the thumb's frame). Coulomb
// stick–slip (eq. 2): the anchor holds while F^T ≤ μ_s·F^N; otherwise it slides so that
// F^T = μ_k·F^N, and stays kinetic until F^T falls to μ_k·F^N. The two fingers get equal
// and opposite forces. See docs/grasp.md.
#include "contact/fingertip.hpp"
#include "contact/hertz.hpp"
#include "contact/proxy.hpp"
#include "core/math.hpp"

namespace tactus::contact {

struct FingerContactParams {
  FingerpadParameters normal_law;      ///< eq. 1, b and m
  double tangential_stiffness = 2000;  ///< of the anchor spring, N/m
  double static_friction = 1.0;        ///< μ_s, skin on skin
  double kinetic_friction = 0.8;       ///< μ_k ≤ μ_s
};

/// Contact memory between steps.
struct FingerContactState {
  bool in_contact = false;
  FrictionState friction = FrictionState::none;
  Vec3 anchor_on_thumb = Vec3::Zero();  ///< the anchor, thumb frame, m
  Vec3 anchor_on_index = Vec3::Zero();  ///< the index's material point tied to it, index frame, m
};

struct FingerContactResult {
  bool in_contact = false;
  FrictionState friction = FrictionState::none;
  double depth = 0.0;                 ///< penetration of the capsules, m
  double normal_force = 0.0;          ///< F^N, N
  double tangential_force = 0.0;      ///< |F^T|, N
  Vec3 normal = Vec3::UnitZ();        ///< unit, from the thumb toward the index
  Vec3 contact_point = Vec3::Zero();  ///< between the two surface points, world
  Vec3 force_on_index = Vec3::Zero(); ///< F^N·n + F^T, N
  Vec3 force_on_thumb = Vec3::Zero(); ///< −force_on_index
};

class FingerContact {
 public:
  /// Throws InputError for bad shapes, a bad law, a non-positive stiffness or friction
  /// coefficients that are negative or with μ_k > μ_s.
  FingerContact(const CapsuleShape& thumb, const CapsuleShape& index, const FingerContactParams& params = {});

  [[nodiscard]] const FingerContactParams& params() const { return params_; }
  [[nodiscard]] const FingerpadLaw& law() const { return law_; }

  /// One step at the fingers' poses. Non-finite poses give no contact and leave the state.
  [[nodiscard]] FingerContactResult update(FingerContactState& state, const Pose& thumb,
                                           const Pose& index) const noexcept;

 private:
  CapsuleShape thumb_;
  CapsuleShape index_;
  FingerContactParams params_;
  FingerpadLaw law_;
};

}  // namespace tactus::contact
