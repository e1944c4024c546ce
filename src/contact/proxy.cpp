#include "contact/proxy.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "core/error.hpp"

namespace tactus::contact {
namespace {

/// The distances an update works with, all from the proxy's centre to the surface.
struct Radii {
  double sweep;    ///< r + skin: a sweep stops the proxy here
  double plane;    ///< r + 2·skin: constraint planes and push-outs put it here, clear of the sweep radius
  double overlap;  ///< r + skin/2: closer than this, the surface has moved into the proxy
  double tiny;     ///< 1e-4·skin: shorter motions are no motion; plane feasibility tolerance
};

Radii radii_of(const ProxyParams& p) {
  return {p.radius + p.skin, p.radius + 2.0 * p.skin, p.radius + 0.5 * p.skin, 1e-4 * p.skin};
}

/// A triangle point counts as inside the face this far outside it (barycentric units).
constexpr double kPrismTolerance = 1e-9;

struct Slide {
  Vec3 position = Vec3::Zero();
  std::array<ConstraintPlane, kMaxProxyPlanes> planes{};
  int count = 0;
  int sweeps = 0;
};

/// Adds the plane of a new hit. A plane nearly parallel to one already there replaces it (the
/// same constraint met again, or a coplanar neighbour); when the set is full, the plane
/// farthest from the proxy (the one it has left behind) gives way.
void add_plane(Slide& s, const ConstraintPlane& plane) {
  for (int i = 0; i < s.count; ++i)
    if (s.planes[static_cast<std::size_t>(i)].normal.dot(plane.normal) > 1.0 - 1e-9) {
      s.planes[static_cast<std::size_t>(i)] = plane;
      return;
    }
  if (s.count < kMaxProxyPlanes) {
    s.planes[static_cast<std::size_t>(s.count++)] = plane;
    return;
  }
  std::size_t farthest = 0;
  for (std::size_t i = 1; i < s.planes.size(); ++i)
    if (s.planes[i].signed_distance(s.position) > s.planes[farthest].signed_distance(s.position)) farthest = i;
  s.planes[farthest] = plane;
}

/// Zilles–Salisbury / Ruspini iteration: aim at the closest point to the goal on the planes met
/// so far, sweep toward it, stop at the first contact and add its tangent plane; repeat. Every
/// move is a sweep from a position outside the surface, so the proxy stays outside whatever
/// the planes say; they only decide where it slides.
Slide slide(const Vec3& start, const Vec3& goal, const SurfaceQuery& surface, const Radii& r, int max_iterations) {
  Slide s;
  s.position = start;
  for (int iteration = 0; iteration < max_iterations; ++iteration) {
    Vec3 target;
    if (!closest_point_on_planes(goal, s.planes.data(), s.count, r.tiny, target)) break;
    if ((target - s.position).norm() <= r.tiny) break;
    const SweepHit hit = surface.sweep_sphere(s.position, target, r.sweep);
    ++s.sweeps;
    if (!hit.hit) {
      s.position = target;
      break;
    }
    s.position = hit.center;
    add_plane(s, {hit.normal, hit.normal.dot(hit.point) + r.plane});
  }
  return s;
}

/// Barycentric coordinates of the projection of p onto the plane of (a, b, c) with unit
/// normal n; false for a degenerate triangle.
bool projects_inside(const Vec3& p, const std::array<Vec3, 3>& tri, Vec3& unit_normal) {
  const auto& [a, b, c] = tri;
  const Vec3 n_raw = (b - a).cross(c - a);
  const double len2 = n_raw.squaredNorm();
  if (!(len2 > 0.0)) return false;
  unit_normal = n_raw / std::sqrt(len2);
  const Vec3 q = p - unit_normal.dot(p - a) * unit_normal;
  const double wa = n_raw.dot((c - b).cross(q - b)) / len2;
  const double wb = n_raw.dot((a - c).cross(q - c)) / len2;
  return wa >= -kPrismTolerance && wb >= -kPrismTolerance && 1.0 - wa - wb >= -kPrismTolerance;
}

/// The surface moved since the last update: put the proxy back outside it. First the
/// remembered side of the triangle it was over (this catches a surface that moved right
/// through the proxy, even a thin one), then overlaps with the closest point, and with
/// closed surfaces a proxy found behind its closest point (inside). Returns whether it moved.
bool push_out(Vec3& p, const ProxyState& state, const SurfaceQuery& surface, const Radii& r, bool closed) {
  bool moved = false;
  if (state.side != 0) {
    if (const auto tri = surface.triangle(state.side_triangle)) {
      Vec3 n;
      if (projects_inside(p, *tri, n)) {
        n *= static_cast<double>(state.side);
        const double s = n.dot(p - (*tri)[0]);
        if (s < r.overlap) {
          p += (r.plane - s) * n;
          moved = true;
        }
      }
    }
  }
  // A push can bring the proxy near another triangle (a concave corner): a few rounds.
  for (int round = 0; round < 4; ++round) {
    const ClosestSurfacePoint cp = surface.closest_point(p);
    if (!cp.found) break;
    Vec3 out;
    if (closed && cp.behind) {
      out = cp.normal;
    } else if (cp.distance < r.overlap) {
      out = cp.distance > 0.0 ? Vec3((p - cp.point) / cp.distance) : cp.normal;
    } else {
      break;
    }
    p = cp.point + r.plane * out;
    moved = true;
  }
  return moved;
}

/// Where the stick anchor is now: it moves with the material point it was attached to.
Vec3 tracked_anchor(const ProxyState& state, const SurfaceQuery& surface) {
  Vec3 anchor = state.stick_anchor;
  if (const auto tri = surface.triangle(state.anchor_triangle)) {
    const Vec3 material = state.anchor_barycentric[0] * (*tri)[0] + state.anchor_barycentric[1] * (*tri)[1] +
                          state.anchor_barycentric[2] * (*tri)[2];
    anchor += material - state.anchor_surface_point;
  }
  return anchor;
}

void require(bool ok, const char* key, double value, const char* what) {
  if (!ok) throw InputError(fmt::format("proxy: {} must be {}, got {}", key, what, value));
}

}  // namespace

void validate_proxy_params(const ProxyParams& p) {
  const auto non_negative = [](double v) { return std::isfinite(v) && v >= 0.0; };
  require(non_negative(p.radius), "radius", p.radius, "finite and not negative");
  require(std::isfinite(p.skin) && p.skin > 0.0, "skin", p.skin, "positive");
  require(std::isfinite(p.stiffness) && p.stiffness > 0.0, "stiffness", p.stiffness, "positive");
  require(non_negative(p.damping), "damping", p.damping, "finite and not negative");
  require(non_negative(p.static_friction), "static_friction", p.static_friction, "finite and not negative");
  require(non_negative(p.kinetic_friction), "kinetic_friction", p.kinetic_friction, "finite and not negative");
  require(p.kinetic_friction <= p.static_friction, "kinetic_friction", p.kinetic_friction,
          "at most static_friction");
  require(non_negative(p.slip_damping), "slip_damping", p.slip_damping, "finite and not negative");
  require(p.max_iterations >= 1 && p.max_iterations <= 100, "max_iterations", p.max_iterations,
          "between 1 and 100");
}

ProxyState make_proxy_state(const Vec3& position) {
  ProxyState state;
  state.position = position;
  state.stick_anchor = position;
  return state;
}

bool closest_point_on_planes(const Vec3& goal, const ConstraintPlane* planes, int count, double tolerance,
                             Vec3& out) {
  // The optimum is the projection of the goal onto the intersection of its active planes
  // (at most three independent ones), and no feasible point is closer: so the closest
  // feasible projection over all subsets of up to three planes is the optimum.
  double best = std::numeric_limits<double>::infinity();
  const auto consider = [&](const Vec3& x) {
    for (int j = 0; j < count; ++j)
      if (planes[j].signed_distance(x) < -tolerance) return;
    const double d2 = (x - goal).squaredNorm();
    if (d2 < best) {
      best = d2;
      out = x;
    }
  };
  constexpr double kDegenerate = 1e-12;  // Gram determinants below this: (nearly) dependent normals
  consider(goal);
  for (int i = 0; i < count; ++i) consider(goal - planes[i].signed_distance(goal) * planes[i].normal);
  for (int i = 0; i < count; ++i)
    for (int j = i + 1; j < count; ++j) {
      const Vec3 &ni = planes[i].normal, &nj = planes[j].normal;
      const double c = ni.dot(nj), det = 1.0 - c * c;
      if (!(det > kDegenerate)) continue;
      const double ri = planes[i].signed_distance(goal), rj = planes[j].signed_distance(goal);
      const double li = (ri - c * rj) / det, lj = (rj - c * ri) / det;
      consider(goal - li * ni - lj * nj);
    }
  for (int i = 0; i < count; ++i)
    for (int j = i + 1; j < count; ++j)
      for (int k = j + 1; k < count; ++k) {
        Mat3 n;
        n.row(0) = planes[i].normal.transpose();
        n.row(1) = planes[j].normal.transpose();
        n.row(2) = planes[k].normal.transpose();
        const Mat3 gram = n * n.transpose();
        if (!(gram.determinant() > kDegenerate)) continue;
        const Vec3 residual(planes[i].signed_distance(goal), planes[j].signed_distance(goal),
                            planes[k].signed_distance(goal));
        const Vec3 lambda = gram.inverse() * residual;
        consider(goal - n.transpose() * lambda);
      }
  return best < std::numeric_limits<double>::infinity();
}

ProxyResult update_proxy(const ProxyParams& params, ProxyState& state, const Vec3& goal, const Vec3& goal_velocity,
                         double dt, const SurfaceQuery& surface) {
  ProxyResult result;
  result.position = state.position;
  if (!goal.allFinite() || !goal_velocity.allFinite() || !state.position.allFinite() || !std::isfinite(dt) ||
      dt < 0.0) {
    result.input_rejected = true;
    return result;
  }
  const Radii r = radii_of(params);
  const Vec3 previous = state.position;
  Vec3 p = state.position;
  result.pushed_out = push_out(p, state, surface, r, params.closed_surfaces);

  // The frictionless proxy: where the goal would put it.
  const Slide free = slide(p, goal, surface, r, params.max_iterations);
  result.sweeps = free.sweeps;
  const double depth = (free.position - goal).norm();
  const bool in_contact = depth > r.tiny;

  // Friction cone (seed 002 §V-C): with n the reaction direction and the anchor a (the
  // proxy's attachment point) on the contact plane, Fn = k·depth and |Ft| = k·|a − x_free|.
  // Stick while |Ft| ≤ μ·Fn (μs when sticking, μk when slipping); otherwise slip to the
  // kinetic cone |Ft| = μk·Fn, at the speed (|Ft| − μk·Fn)/b_p when slip_damping b_p > 0.
  Vec3 target = free.position;
  FrictionState friction = FrictionState::none;
  if (in_contact) {
    friction = FrictionState::slip;
    if (params.static_friction > 0.0) {
      if (state.in_contact && state.friction != FrictionState::none) {
        const Vec3 n = (free.position - goal) / depth;
        const Vec3 anchor = tracked_anchor(state, surface);
        const Vec3 on_plane = anchor - n.dot(anchor - free.position) * n;
        const Vec3 tangential = on_plane - free.position;
        const double lag = tangential.norm();
        const double mu =
            state.friction == FrictionState::slip ? params.kinetic_friction : params.static_friction;
        if (lag <= mu * depth + r.tiny) {
          friction = FrictionState::stick;
          target = on_plane;
        } else {
          const Vec3 cone = free.position + (params.kinetic_friction * depth / lag) * tangential;
          double step =
              params.slip_damping > 0.0 ? std::min(1.0, params.stiffness * dt / params.slip_damping) : 1.0;
          // The last sliver of a damped approach is taken at once, so that the proxy settles
          // on the cone (and sticks) instead of creeping toward it forever.
          if ((1.0 - step) * (lag - params.kinetic_friction * depth) <= 10.0 * r.tiny) step = 1.0;
          target = on_plane + step * (cone - on_plane);
        }
      } else {
        friction = FrictionState::stick;  // first touch: held where it landed
      }
    }
  }
  Vec3 x = free.position;
  if ((target - free.position).norm() > r.tiny) {
    const Slide held = slide(p, target, surface, r, params.max_iterations);
    result.sweeps += held.sweeps;
    x = held.position;
  }

  const ClosestSurfacePoint cp = surface.closest_point(x);
  if (in_contact) {
    result.force = params.stiffness * (x - goal);
    const Vec3 moved = state.surface_replaced ? Vec3::Zero() : Vec3(x - previous);
    if (dt > 0.0) result.force += params.damping * (moved / dt - goal_velocity);
    result.depth = depth;
    if (cp.found) {
      result.contact_point = cp.point;
      result.contact_normal = cp.distance > 0.0 ? Vec3((x - cp.point) / cp.distance) : cp.normal;
      result.triangle = cp.triangle;
      result.barycentric = cp.barycentric;
    }
  }
  result.position = x;
  result.in_contact = in_contact;
  result.friction = friction;

  const bool keep_anchor = friction == FrictionState::stick && state.friction == FrictionState::stick;
  state.position = x;
  state.surface_replaced = false;
  state.in_contact = in_contact;
  state.friction = friction;
  state.plane_count = 0;
  for (int i = 0; i < free.count; ++i) {
    const ConstraintPlane& plane = free.planes[static_cast<std::size_t>(i)];
    if (plane.signed_distance(free.position) <= params.skin)
      state.planes[static_cast<std::size_t>(state.plane_count++)] = plane;
  }
  if (!keep_anchor) {
    state.stick_anchor = x;
    state.anchor_triangle = cp.found ? cp.triangle : -1;
    state.anchor_barycentric = cp.barycentric;
    state.anchor_surface_point = cp.point;
  }
  state.side_triangle = -1;
  state.side = 0;
  if (cp.found && cp.distance > 0.0) {
    if (const auto tri = surface.triangle(cp.triangle)) {
      Vec3 n;
      if (projects_inside(x, *tri, n)) {
        state.side_triangle = cp.triangle;
        state.side = n.dot(x - (*tri)[0]) >= 0.0 ? std::int8_t{1} : std::int8_t{-1};
      }
    }
  }
  return result;
}

ConstraintPlane blend_planes(const ConstraintPlane& from, const ConstraintPlane& to, double s) {
  if (!(s > 0.0)) return from;
  if (!(s < 1.0)) return to;
  const Vec3 normal = (1.0 - s) * from.normal + s * to.normal;
  const double offset = (1.0 - s) * from.offset + s * to.offset;
  const double len = normal.norm();
  // Opposite normals cancel halfway: no plane there, so hand over from one to the other.
  if (!(len > 1e-9)) return s < 0.5 ? from : to;
  return {normal / len, offset / len};
}

PlaneInterpolator::PlaneInterpolator(double blend_time) : blend_time_(blend_time) {
  require(std::isfinite(blend_time) && blend_time >= 0.0, "plane blend_time", blend_time,
          "finite and not negative");
}

void PlaneInterpolator::set_target(const ConstraintPlane& plane, double now) {
  from_ = has_plane_ ? at(now) : plane;
  to_ = plane;
  start_ = now;
  has_plane_ = true;
}

ConstraintPlane PlaneInterpolator::at(double now) const {
  if (!(blend_time_ > 0.0)) return to_;
  return blend_planes(from_, to_, (now - start_) / blend_time_);
}

}  // namespace tactus::contact
