#pragma once
// A fingertip on a fabric (seed 002 §V-C, contact states IV–VII): the V-proxy
// (contact/fabric_proxy.hpp) against a local patch of the fabric that deforms at the haptic
// rate between simulation steps (the fabric's own linearized springs, border at constant
// velocity, seed §IV). The proxy keeps to its finger's side of the thin sheet: the thumb
// touches the front, the index the back.
//
// With a partner finger (the other of a thumb–index pair, each on its own device and loop)
// it renders the rest of Table I from the partner's newest pose (FrameInputs::peer): the
// fingers touching each other without fabric (II, III; contact/finger_contact.hpp) and the
// fabric squeezed between them (VIII, IX; contact/grasp.hpp). Each finger's loop runs the
// pair's laws on its own patch and takes its own finger's share; both see the same laws, so
// the forces are equal and opposite up to one haptic period of the partner's motion. It
// classifies the state every frame (Rendering::contact_state). See docs/grasp.md.
#include <optional>
#include <vector>

#include "contact/fabric_proxy.hpp"
#include "contact/finger_contact.hpp"
#include "contact/grasp.hpp"
#include "haptics/algorithms/on_patch.hpp"

namespace tactus::haptics {

/// The pair's side of a fingertip: its partner and the laws between them.
struct TwoFingerParams {
  contact::CapsuleShape own;      ///< this fingertip, with its pad normal
  contact::CapsuleShape partner;  ///< the other one, in its own frame
  contact::FingerContactParams finger_contact;  ///< skin on skin (eq. 1, eq. 2)
  double fabric_thickness = contact::GraspParams{}.fabric_thickness;  ///< [m]
};

class FabricProxyOnPatch final : public OnPatch {
 public:
  /// Throws InputError for parameters out of range (contact::validate, FingerContact, Grasp).
  FabricProxyOnPatch(const contact::FabricProxyParams& params, contact::LocalModelKind kind,
                     contact::PatchCapacity capacity, bool spread_over_disc,
                     const std::optional<TwoFingerParams>& two_fingers = std::nullopt);

  [[nodiscard]] std::unique_ptr<AlgorithmState> make_state() const override;
  [[nodiscard]] const contact::FabricProxyParams& params() const { return proxy_.params(); }

 private:
  struct State final : PatchState {
    State(contact::LocalModelKind kind, const contact::PatchCapacity& capacity);
    contact::FabricProxyState proxy;
    bool started = false;
    std::vector<std::int32_t> candidates;  ///< 0, 1, ... over the patch's triangles
    std::int32_t surface_triangle = -1;    ///< the body's triangle the proxy rests on, across an update
    contact::FingerContactState fingers;
    contact::PointGraspState grasp;
    bool grasping = false;  ///< the last frame rendered the grasp
    /// This finger's part of what the grasp does to the fabric, the last frame: of the hold
    /// (the pads' squeezes cancel on the fabric), across the pads' plane for the thumb and
    /// along it for the index, ramped in with the grasp [N].
    Vec3 fabric_share = Vec3::Zero();
    Vec3 pads_normal = Vec3::UnitZ();  ///< the pads' plane's normal, the last frame
    /// The hand-over between the grasp and the V-proxy: when the last one began, the force and
    /// torque it began from, and those of the last frame.
    double handed_over_at = -1.0;
    Vec3 handed_over_from = Vec3::Zero(), handed_over_torque = Vec3::Zero();
    Vec3 last_force = Vec3::Zero(), last_torque = Vec3::Zero();
    /// The material point the grasp holds: patch triangle, barycentric, the body's triangle.
    std::int32_t held_triangle = -1;
    Vec3 held_barycentric = Vec3::Zero();
    std::int32_t held_surface_triangle = -1;
  };
  void begin(const FrameInputs& frame, PatchState& state) const override;
  void patch_replacing(PatchState& state) const override;
  void patch_replaced(PatchState& state) const override;
  [[nodiscard]] Rendering against(const FrameInputs& frame, PatchState& state, bool trial) const override;
  void advance(const FrameInputs& frame, const Rendering& rendered, const Reaction& reaction, bool on,
               const contact::PatchContact& on_patch, PatchState& state, ContactLoad& load) const override;

  /// The V-proxy alone (states IV–VII for this finger).
  [[nodiscard]] Rendering on_fabric(const FrameInputs& frame, State& state, contact::FabricProxyState& proxy) const;
  /// The pair's laws on top of the V-proxy, and the state of Table I.
  void with_partner(const FrameInputs& frame, State& state, bool trial, contact::FabricProxyState& proxy,
                    Rendering& out) const;

  contact::FabricProxy proxy_;
  bool is_thumb_ = true;  ///< touches the front (side +1)
  std::optional<contact::FingerContact> fingers_;
  std::optional<contact::PointGrasp> grasp_;
};

}  // namespace tactus::haptics
