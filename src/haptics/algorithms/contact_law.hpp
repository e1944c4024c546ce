#pragma once
// The normal force law of a finger's contact spheres against tissue: a penalty spring, Hertz
// contact with the tissue's curvature (seed 000 §3.1–3.2), or the Pawluk–Howe fingerpad law
// (seed 002 eq. 1). Shared by the sphere-set algorithms on a plane and on a patch.
#include <optional>
#include <vector>

#include "contact/hertz.hpp"
#include "core/math.hpp"
#include "haptics/force_algorithm.hpp"

namespace tactus::haptics {

/// A contact sphere in the tool frame.
struct ToolSphere {
  Vec3 offset = Vec3::Zero();  ///< [m]
  double radius = 0.0;         ///< [m]
};

class ContactLaw {
 public:
  /// A penalty spring of `stiffness` [N/m] (editable while the run goes on).
  static ContactLaw penalty(double stiffness) { return ContactLaw(stiffness, std::nullopt, std::nullopt); }
  static ContactLaw hertz(const contact::HertzParameters& p) { return ContactLaw(0.0, contact::HertzContact(p), std::nullopt); }
  static ContactLaw fingerpad(const contact::FingerpadParameters& p) {
    return ContactLaw(0.0, std::nullopt, contact::FingerpadLaw(p));
  }

  /// The normal force [N] at penetration `depth` [m] into tissue of mean curvature
  /// `mean_curvature` [1/m]; `stiffness` is the penalty's current (possibly edited) value.
  [[nodiscard]] double force(double depth, double mean_curvature, double stiffness) const {
    return hertz_       ? hertz_->evaluate(depth, mean_curvature).force
           : fingerpad_ ? fingerpad_->force(depth)
                        : stiffness * depth;
  }
  [[nodiscard]] bool is_penalty() const { return !hertz_ && !fingerpad_; }
  /// What the force becomes, as a factor, where the pressed material is `tissue` instead of
  /// the law's own: E*(finger, tissue) / E*(finger, law's tissue) for Hertz, whose force is
  /// proportional to E* in every regime; 1 for the other laws, which hold no tissue modulus.
  /// `tissue` must be valid (E > 0, ν in [0, 0.5]).
  [[nodiscard]] double modulus_factor(const contact::ElasticMaterial& tissue) const noexcept {
    if (!hertz_) return 1.0;
    return contact::effective_modulus(hertz_->parameters().finger, tissue) / hertz_->effective_modulus();
  }
  /// What the viewer's panel may edit of a finger with this law: a penalty's stiffness.
  [[nodiscard]] EditableSurface editable_surface(bool has_spheres) const {
    if (!is_penalty() || !has_spheres) return {};
    return {EditableSurface::Kind::penalty, {stiffness_, 0.0, 0.0}};
  }
  /// The penalty's stiffness as the scene set it [N/m] (0 for the other laws).
  [[nodiscard]] double stiffness() const { return stiffness_; }

 private:
  ContactLaw(double stiffness, std::optional<contact::HertzContact> hertz, std::optional<contact::FingerpadLaw> pad)
      : stiffness_(stiffness), hertz_(std::move(hertz)), fingerpad_(std::move(pad)) {}
  double stiffness_;
  std::optional<contact::HertzContact> hertz_;
  std::optional<contact::FingerpadLaw> fingerpad_;
};

}  // namespace tactus::haptics
