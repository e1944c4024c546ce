#include "contact/grasp.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "core/error.hpp"

namespace tactus::contact {
namespace {

/// Both fingers with unit orientations, their capsules, and how deep their pads squeeze the
/// fabric (its thickness minus the capsules' gap).
struct Pads {
  Pose thumb, index;
  Capsule thumb_capsule, index_capsule;
  CapsulePair pair;
  double depth = 0.0;
};

Pads pads_of(const GraspParams& p, const Pose& thumb_pose, const Pose& index_pose) {
  Pads pads;
  pads.thumb = thumb_pose;
  pads.index = index_pose;
  pads.thumb.orientation.normalize();
  pads.index.orientation.normalize();
  pads.thumb_capsule = posed(p.thumb, pads.thumb);
  pads.index_capsule = posed(p.index, pads.index);
  pads.pair = capsule_capsule(pads.thumb_capsule, pads.index_capsule);
  pads.depth = p.fabric_thickness - pads.pair.signed_distance;
  return pads;
}

/// The shared frame, with hysteresis on the parallel rule: a grasp that uses it leaves it only
/// beyond 1.5 times the threshold, so the frame does not flip back and forth.
SharedFrame frame_of(const GraspParams& p, const Pads& pads, bool active, const SharedFrame& last) {
  const double sine = std::sin(p.parallel_angle);
  const double threshold = active && last.parallel ? 1.5 * sine : sine;
  return shared_frame(p.thumb, pads.thumb, p.index, pads.index, threshold);
}

Vec3 axis_direction(const Capsule& c) {
  const Vec3 d = c.tip - c.base;
  const double len = d.norm();
  return len > 0.0 ? Vec3(d / len) : Vec3::Zero();
}

/// `v` with its part along unit `n` removed, normalised; zero if little is left.
Vec3 across_normal(const Vec3& v, const Vec3& n) {
  const Vec3 w = v - v.dot(n) * n;
  const double len = w.norm();
  return len > 1e-6 ? Vec3(w / len) : Vec3::Zero();
}

void require_grasp(bool ok, const char* key, double value, const char* what) {
  if (!ok) throw InputError(fmt::format("grasp: {} must be {}, got {}", key, what, value));
}

}  // namespace

SharedFrame shared_frame(const CapsuleShape& thumb, const Pose& thumb_pose, const CapsuleShape& index,
                         const Pose& index_pose, double parallel_sine) noexcept {
  const Capsule ct = posed(thumb, thumb_pose), ci = posed(index, index_pose);
  const Vec3 nt = pad_normal(thumb, thumb_pose), ni = pad_normal(index, index_pose);
  // Each pad plane touches its capsule: it runs along the axis, one radius out. The pad
  // centres (not the capsules' closest points, which jump along the axes as they turn
  // parallel) place the origin, so that the frame moves continuously with the fingers.
  const Vec3 pt = 0.5 * (ct.base + ct.tip) + ct.radius * nt, pi = 0.5 * (ci.base + ci.tip) + ci.radius * ni;
  const Vec3 mid = 0.5 * (pt + pi);

  SharedFrame f;
  Vec3 e3;
  double offset = 0.0;
  const Vec3 bisector = nt - ni;
  const double len = bisector.norm();
  if (len > 1e-9) {
    e3 = bisector / len;
    offset = (nt.dot(pt) - ni.dot(pi)) / len;
  } else {
    // The pads face the same way (no pinch): fall back on the capsules' contact normal.
    e3 = capsule_capsule(ct, ci).normal;
    offset = e3.dot(mid);
  }
  f.origin = mid - (e3.dot(mid) - offset) * e3;

  const Vec3 line = nt.cross(ni);
  f.pad_sine = line.norm();
  Vec3 e1 = f.pad_sine >= parallel_sine ? across_normal(line, e3) : Vec3::Zero();
  if (e1.isZero()) {
    f.parallel = true;
    e1 = across_normal(axis_direction(ct), e3);
    if (e1.isZero()) e1 = across_normal(axis_direction(ci), e3);
    if (e1.isZero()) {
      // Both axes along the normal (no pad contact): any direction across it.
      const Vec3 helper = std::abs(e3.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
      e1 = across_normal(helper, e3);
    }
  }
  f.axes.col(0) = e1;
  f.axes.col(1) = e3.cross(e1);
  f.axes.col(2) = e3;
  return f;
}

Grasp::Grasp(const GraspParams& params)
    : params_(params), squeeze_(params.squeeze_law), hold_(params.hold_law) {
  validate(params.thumb, "grasp: thumb");
  validate(params.index, "grasp: index");
  const auto non_negative = [](double v) { return std::isfinite(v) && v >= 0.0; };
  require_grasp(non_negative(params.fabric_thickness), "fabric_thickness", params.fabric_thickness,
                "finite and not negative");
  require_grasp(non_negative(params.capture_distance), "capture_distance", params.capture_distance,
                "finite and not negative");
  require_grasp(non_negative(params.static_friction), "static_friction", params.static_friction,
                "finite and not negative");
  require_grasp(non_negative(params.kinetic_friction) && params.kinetic_friction <= params.static_friction,
                "kinetic_friction", params.kinetic_friction, "finite, not negative and at most static_friction");
  require_grasp(std::isfinite(params.parallel_angle) && params.parallel_angle >= 0.0 && params.parallel_angle < 1.0,
                "parallel_angle", params.parallel_angle, "in [0, 1) rad");
  require_grasp(params.max_particles >= 1 && params.max_particles <= 1'000'000, "max_particles",
                static_cast<double>(params.max_particles), "between 1 and 1e6");
}

GraspState Grasp::make_state() const {
  GraspState s;
  s.held.reserve(params_.max_particles);
  return s;
}

GraspResult Grasp::update(GraspState& state, const Pose& thumb_pose, const Pose& index_pose,
                          std::span<const Vec3> positions, std::span<const std::int32_t> candidates) const noexcept {
  GraspResult out;
  if (!finite_pose(thumb_pose) || !finite_pose(index_pose)) {
    out.input_rejected = true;
    return out;
  }
  const GraspParams& p = params_;
  const Pads both = pads_of(p, thumb_pose, index_pose);
  const Capsule& ct = both.thumb_capsule;
  const Capsule& ci = both.index_capsule;
  const CapsulePair& pads = both.pair;
  const double depth = both.depth;

  const auto let_go = [&] {
    state.active = false;
    state.friction = FrictionState::none;
    state.held.clear();
    out.held = state.held;
    return out;
  };
  if (!(depth > 0.0)) return let_go();

  // Targets carried over when the frame's rule changes (the rules give frames turned about
  // e3), so the targets never jump.
  const SharedFrame frame = frame_of(p, both, state.active, state.frame);
  if (state.active && frame.parallel != state.frame.parallel)
    for (HeldParticle& h : state.held) h.anchor = frame.to_local(state.frame.to_world(h.anchor)).head<2>();

  // Who is caught: within reach of both capsules.
  const auto position_of = [&](std::int32_t i, Vec3& x) {
    if (i < 0 || static_cast<std::size_t>(i) >= positions.size()) return false;
    x = positions[static_cast<std::size_t>(i)];
    return x.allFinite();
  };
  const auto caught = [&](const Vec3& x) {
    return point_capsule(x, ct).signed_distance <= p.capture_distance &&
           point_capsule(x, ci).signed_distance <= p.capture_distance;
  };
  if (!state.active) state.held.clear();
  std::size_t kept = 0;
  for (const HeldParticle& h : state.held) {
    Vec3 x;
    if (position_of(h.index, x) && caught(x)) state.held[kept++] = h;
  }
  state.held.resize(kept);  // shrinking: no allocation
  for (const std::int32_t i : candidates) {
    Vec3 x;
    if (!position_of(i, x) || !caught(x)) continue;
    if (std::any_of(state.held.begin(), state.held.end(), [i](const HeldParticle& h) { return h.index == i; }))
      continue;
    if (state.held.size() >= state.held.capacity()) {
      ++out.ignored;
      continue;
    }
    HeldParticle h;
    h.index = i;
    h.anchor = frame.to_local(x).head<2>();  // held where it is, on the contact plane
    state.held.push_back(h);
  }
  if (state.held.empty()) return let_go();

  // Particle forces toward the targets shifted by `shift` (in the frame); returns the sum of
  // their parts along the contact plane.
  const Vec3 e3 = frame.normal();
  const double share = 1.0 / static_cast<double>(state.held.size());
  const auto pull = [&](const Vec2& shift) {
    Vec3 tangential = Vec3::Zero();
    for (HeldParticle& h : state.held) {
      h.target = frame.to_world(h.anchor + shift);
      const Vec3 d = h.target - positions[static_cast<std::size_t>(h.index)];
      const double dist = d.norm();
      h.force = dist > 0.0 ? Vec3((share * hold_.force(dist) / dist) * d) : Vec3::Zero();
      tangential += h.force - h.force.dot(e3) * e3;
    }
    return tangential;
  };

  const double squeeze = squeeze_.force(depth);
  Vec3 load = pull(Vec2::Zero());
  const double mu =
      state.active && state.friction == FrictionState::slip ? p.kinetic_friction : p.static_friction;
  FrictionState friction = FrictionState::stick;
  if (load.norm() > mu * squeeze) {
    // Slip: the targets slide together, along the pull of the fabric (against the load),
    // until the load along its first direction is μ_k·F^N. Illinois-safeguarded regula falsi
    // on the slide length λ.
    friction = FrictionState::slip;
    const Vec3 dir0 = load.normalized();
    const Vec2 dir(-dir0.dot(frame.axes.col(0)), -dir0.dot(frame.axes.col(1)));
    const double goal = p.kinetic_friction * squeeze;
    const auto excess = [&](double lambda) { return pull(lambda * dir.normalized()).dot(dir0) - goal; };
    double lo = 0.0, g_lo = load.norm() - goal;
    double hi = 0.0;
    for (const HeldParticle& h : state.held) {
      const Vec3 d = positions[static_cast<std::size_t>(h.index)] - h.target;
      hi = std::max(hi, (d - d.dot(e3) * e3).norm());
    }
    hi = std::max(hi, 1e-9);
    double g_hi = excess(hi);
    for (int i = 0; i < 40 && g_hi > 0.0; ++i) g_hi = excess(hi *= 2.0);
    double lambda = hi;
    if (g_hi < 0.0) {
      const double tolerance = 1e-10 * (goal + load.norm());
      int side = 0;
      for (int i = 0; i < 60; ++i) {
        lambda = (lo * g_hi - hi * g_lo) / (g_hi - g_lo);
        const double g = excess(lambda);
        if (std::abs(g) <= tolerance) break;
        if (g > 0.0) {
          lo = lambda;
          g_lo = g;
          if (side == +1) g_hi *= 0.5;
          side = +1;
        } else {
          hi = lambda;
          g_hi = g;
          if (side == -1) g_lo *= 0.5;
          side = -1;
        }
      }
    }
    const Vec2 shift = lambda * dir.normalized();
    for (HeldParticle& h : state.held) h.anchor += shift;
    load = pull(Vec2::Zero());
  }

  // Each pad pushes the particles on its side toward the plane and takes the reaction; both
  // grip the fabric, so they share the reaction of the tangential pull. The pads squeeze
  // each other along the capsules' normal.
  Vec3 thumb = -squeeze * pads.normal - 0.5 * load, index = squeeze * pads.normal - 0.5 * load;
  for (const HeldParticle& h : state.held) {
    const Vec3 normal_part = h.force.dot(e3) * e3;
    const double side = e3.dot(positions[static_cast<std::size_t>(h.index)] - frame.origin);
    if (side < 0.0) {
      thumb -= normal_part;
    } else if (side > 0.0) {
      index -= normal_part;
    } else {
      thumb -= 0.5 * normal_part;
      index -= 0.5 * normal_part;
    }
  }

  state.active = true;
  state.friction = friction;
  state.frame = frame;
  out.active = true;
  out.friction = friction;
  out.frame = frame;
  out.squeeze_depth = depth;
  out.squeeze_force = squeeze;
  out.squeeze_normal = pads.normal;
  out.tangential_load = load.norm();
  out.force_on_thumb = thumb;
  out.force_on_index = index;
  out.held = state.held;
  return out;
}

PointGrasp::PointGrasp(const GraspParams& params, double hold_stiffness)
    : grasp_(params), squeeze_(params.squeeze_law), hold_stiffness_(hold_stiffness) {
  require_grasp(std::isfinite(hold_stiffness) && hold_stiffness > 0.0, "hold_stiffness", hold_stiffness,
                "positive and finite");
}

void PointGrasp::move_hold(PointGraspState& state, const Vec3& from, const Vec3& to) noexcept {
  if (!state.active || !from.allFinite() || !to.allFinite()) return;
  state.anchor += (state.frame.to_local(to) - state.frame.to_local(from)).head<2>();
}

PointGraspResult PointGrasp::update(PointGraspState& state, const Pose& thumb_pose, const Pose& index_pose,
                                    const Vec3& point, bool may_start) const noexcept {
  PointGraspResult out;
  const auto let_go = [&] {
    state = PointGraspState{};
    return out;
  };
  if (!finite_pose(thumb_pose) || !finite_pose(index_pose)) {
    out.input_rejected = true;
    return let_go();
  }
  const GraspParams& p = grasp_.params();
  const Pads both = pads_of(p, thumb_pose, index_pose);
  const CapsulePair& pads = both.pair;
  const double depth = both.depth;
  if (!(depth > 0.0) || !point.allFinite() || !(state.active || may_start)) return let_go();

  // The anchor carried over when the frame's rule changes, so the target never jumps.
  const SharedFrame frame = frame_of(p, both, state.active, state.frame);
  if (!state.active)
    state.anchor = frame.to_local(point).head<2>();  // held where it projects onto the plane
  else if (frame.parallel != state.frame.parallel)
    state.anchor = frame.to_local(state.frame.to_world(state.anchor)).head<2>();

  const double squeeze = squeeze_.force(depth);
  const Vec3 e3 = frame.normal();
  Vec3 target = frame.to_world(state.anchor);
  Vec3 hold = hold_stiffness_ * (target - point);
  Vec3 tangential = hold - hold.dot(e3) * e3;
  const double mu = state.active && state.friction == FrictionState::slip ? p.kinetic_friction : p.static_friction;
  FrictionState friction = FrictionState::stick;
  if (tangential.norm() > mu * squeeze) {
    // Slip: the anchor slides toward the point until the pull along the plane is μ_k·F^N.
    friction = FrictionState::slip;
    const Vec3 along = tangential.normalized();
    const Vec3 on_plane = target - (target - point).dot(along) * along;  // the target with no pull along `along`
    target = on_plane + (p.kinetic_friction * squeeze / hold_stiffness_) * along;
    state.anchor = frame.to_local(target).head<2>();
    target = frame.to_world(state.anchor);
    hold = hold_stiffness_ * (target - point);
  }
  // Across the plane a pad pushes the fabric with at most the squeeze: the hold into the
  // plane is bounded by F^N, so it fades with the squeeze as the pads open.
  const double across = hold.dot(e3);
  if (std::abs(across) > squeeze) hold -= (across - std::copysign(squeeze, across)) * e3;

  state.active = true;
  state.friction = friction;
  state.frame = frame;
  out.active = true;
  out.friction = friction;
  out.frame = frame;
  out.squeeze_depth = depth;
  out.squeeze_force = squeeze;
  out.target = target;
  out.hold = hold;
  out.force_on_thumb = -squeeze * pads.normal - 0.5 * hold;
  out.force_on_index = squeeze * pads.normal - 0.5 * hold;
  return out;
}

}  // namespace tactus::contact
