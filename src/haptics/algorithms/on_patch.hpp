#pragma once
// The base of the algorithms that touch a local patch of the tissue (contact/local_model.hpp):
// a piece of the surface around the tool that the simulation cuts at each of its steps and
// that deforms at the haptic rate between them (a mass-spring patch, or the compliance
// condensed from the body). A new patch is a model update: with smoothing on, the force of
// the old patch and of the new one are both measured at this frame.
#include "contact/local_model.hpp"
#include "contact/surface_query.hpp"
#include "haptics/force_algorithm.hpp"

namespace tactus::haptics {

class OnPatch : public ForceAlgorithm {
 public:
  /// `kind` and `capacity` as the device's channel requests the patch; `spread_over_disc`: a
  /// contact dents the patch over its contact disc instead of its triangle.
  OnPatch(contact::LocalModelKind kind, contact::PatchCapacity capacity, bool spread_over_disc)
      : kind_(kind), capacity_(capacity), spread_over_disc_(spread_over_disc) {}

  [[nodiscard]] Rendering render(const FrameInputs& frame, AlgorithmState& state) const final;
  void react(const FrameInputs& frame, const Rendering& rendered, const Reaction& reaction, AlgorithmState& state,
             ContactLoad& load) const final;
  [[nodiscard]] bool simulation_follows_tool() const override { return true; }

 protected:
  struct PatchState : AlgorithmState {
    PatchState(contact::LocalModelKind kind, const contact::PatchCapacity& capacity) : local(kind, capacity) {}
    contact::LocalModel local;
    contact::BruteForceSurfaceQuery no_surface{{}, {}};
    [[nodiscard]] const contact::SurfaceQuery& surface() const { return local.valid() ? local.surface() : no_surface; }
  };
  [[nodiscard]] const contact::PatchCapacity& capacity() const { return capacity_; }
  [[nodiscard]] contact::LocalModelKind kind() const { return kind_; }
  /// The radius a load is spread over: the contact disc's, or −1 for the contact triangle.
  [[nodiscard]] double disc_radius(double contact_radius) const { return spread_over_disc_ ? contact_radius : -1.0; }

  virtual void begin(const FrameInputs& /*frame*/, PatchState& /*state*/) const {}
  /// A new patch is about to replace the old one (still in the state): what remembers the
  /// old one's triangles notes them as the body's surface triangles.
  virtual void patch_replacing(PatchState& /*state*/) const {}
  /// A new patch replaced the old: whatever remembers the old one's triangles forgets them,
  /// or finds them again in the new one.
  virtual void patch_replaced(PatchState& /*state*/) const {}
  /// The force against the patch's current shape. A `trial` measures without changing the state.
  [[nodiscard]] virtual Rendering against(const FrameInputs& frame, PatchState& state, bool trial) const = 0;
  /// The patch moves under the force sent: `on_patch` is the contact scaled to it (triangle
  /// −1: none); `on` whether the tool touches the patch.
  virtual void advance(const FrameInputs& frame, const Rendering& rendered, const Reaction& reaction, bool on,
                       const contact::PatchContact& on_patch, PatchState& state, ContactLoad& load) const = 0;

 private:
  contact::LocalModelKind kind_;
  contact::PatchCapacity capacity_;
  bool spread_over_disc_;
};

}  // namespace tactus::haptics
