#include "haptics/algorithms/on_patch.hpp"

#include <algorithm>

namespace tactus::haptics {

Rendering OnPatch::render(const FrameInputs& f, AlgorithmState& state) const {
  auto& s = static_cast<PatchState&>(state);
  begin(f, s);
  // The local model refers to the channel's patch in place: it takes a new one when one came,
  // or when the one it refers to is no longer the channel's newest (a frame passed without
  // this call); the old one may then be under the simulation's pen and is not read.
  const bool replaced = f.patch && (f.patch_fresh || (&s.local.patch() != f.patch && s.local.valid()));
  // The step is smoothed only from one model to the next, not from none at start, and only
  // while the channel still holds the model being replaced.
  const bool smooth = replaced && f.smoothing && s.local.valid() && &s.local.patch() == f.patch_previous;
  Vec3 before = Vec3::Zero();
  if (smooth) {
    s.local.extrapolate(f.t);
    before = against(f, s, true).force;
  }
  if (replaced) {
    patch_replacing(s);
    s.local.reset(*f.patch, f.t);
    patch_replaced(s);
  } else {
    s.local.extrapolate(f.t);
  }
  Rendering r = against(f, s, false);
  if (smooth) {
    r.model_changed = true;
    r.before = before;
    r.after = r.force;
  }
  r.surface_time = s.local.patch().time;
  r.frame_point = r.touching ? r.point : Vec3::Zero();
  return r;
}

void OnPatch::react(const FrameInputs& f, const Rendering& rendered, const Reaction& reaction, AlgorithmState& state,
                    ContactLoad& load) const {
  auto& s = static_cast<PatchState&>(state);
  const contact::LocalPatch& patch = s.local.patch();
  contact::PatchContact on_patch = rendered.on_patch;
  const bool on = rendered.touching && patch.valid && on_patch.triangle >= 0 && on_patch.triangle < patch.triangle_count;
  load.active = on;
  load.body = patch.body;
  load.triangle = on ? patch.surface_triangle[static_cast<std::size_t>(on_patch.triangle)] : -1;
  load.barycentric = on_patch.barycentric;
  // The patch moves under the force sent (ramped, clamped), its law's slope scaled alike.
  if (on) {
    const double sent_normal = std::max(0.0, reaction.sent.dot(on_patch.normal));
    if (rendered.law_force > 0.0) on_patch.stiffness *= std::min(1.0, sent_normal / rendered.law_force);
    on_patch.force = sent_normal;
    load.stiffness = on_patch.stiffness;
  } else {
    on_patch.triangle = -1;
  }
  advance(f, rendered, reaction, on, on_patch, s, load);
  const double push = load.force.norm();
  if (on && push > 0.0) {
    load.surface_offset = s.local.moved_since_published(on_patch.triangle, on_patch.barycentric).dot(load.force / push);
    load.published_point = s.local.published_point(on_patch.triangle, on_patch.barycentric);
  }
}

}  // namespace tactus::haptics
