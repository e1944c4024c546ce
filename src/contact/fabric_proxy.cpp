#include "contact/fabric_proxy.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "core/error.hpp"

namespace tactus::contact {
namespace {

/// One triangle of the fabric as the finger sees it.
struct Face {
  std::array<std::int32_t, 3> vertices{};
  Vec3 a, b, c;
  Vec3 normal;  ///< unit, toward the finger's side (the triangle normal times `side`)
};

/// The corners of triangle t into out (vertices, a, b, c); false where t or a corner index is
/// out of range.
bool corners_of(std::int32_t t, std::span<const Vec3> positions, std::span<const mesh::Triangle> triangles,
                Face& out) {
  if (t < 0 || static_cast<std::size_t>(t) >= triangles.size()) return false;
  const mesh::Triangle& tri = triangles[static_cast<std::size_t>(t)];
  for (int k = 0; k < 3; ++k) {
    const auto v = tri[static_cast<std::size_t>(k)];
    if (v < 0 || static_cast<std::size_t>(v) >= positions.size()) return false;
  }
  out.vertices = tri;
  out.a = positions[static_cast<std::size_t>(tri[0])];
  out.b = positions[static_cast<std::size_t>(tri[1])];
  out.c = positions[static_cast<std::size_t>(tri[2])];
  return true;
}

/// The unit normal of a face whose corners are set, toward `side`; false where it is
/// degenerate or not finite.
bool orient(Face& f, int side) {
  const Vec3 n = (f.b - f.a).cross(f.c - f.a);
  const double len = n.norm();
  if (!(len > 0.0) || !std::isfinite(len)) return false;
  f.normal = (static_cast<double>(side) / len) * n;
  return true;
}

bool face_of(std::int32_t t, std::span<const Vec3> positions, std::span<const mesh::Triangle> triangles, int side,
             Face& out) {
  return corners_of(t, positions, triangles, out) && orient(out, side);
}

Vec3 material_point(const Face& f, const Vec3& bary) { return bary[0] * f.a + bary[1] * f.b + bary[2] * f.c; }

/// The capsule (axis x + e0 → x + e1, radius r) is on the finger's side of the face's plane
/// exactly when normal·x ≥ offset: the configuration-space plane of the face.
double plane_offset(const Face& f, const Vec3& e0, const Vec3& e1, double r) {
  return f.normal.dot(f.a) + r - std::min(f.normal.dot(e0), f.normal.dot(e1));
}

struct Nearest {
  std::int32_t triangle = -1;
  Face face;
  SegmentTrianglePair pair;
};

/// The candidate triangle closest to the capsule's axis at translation x (ties: the first).
/// `hint`, a candidate likely to be near (the proxy's last triangle; −1: none), only speeds
/// the search up: the result is the same triangle with or without it.
Nearest nearest_face(const Vec3& x, const Vec3& e0, const Vec3& e1, std::span<const Vec3> positions,
                     std::span<const mesh::Triangle> triangles, std::span<const std::int32_t> candidates, int side,
                     std::int32_t hint = -1) {
  // The axis is at least (distance to a triangle's bounding sphere) from it: a triangle
  // whose sphere lies beyond a distance some triangle reaches (with 1 pm of slack for
  // rounding) cannot be nearer, and its exact test, most of a haptic frame's cost, is
  // skipped. That distance starts at the hint's, so the cull works from the first
  // candidate; the choice among the rest is made in candidate order, as without it.
  constexpr double kSlack = 1e-12;
  Nearest best;
  best.pair.distance = std::numeric_limits<double>::infinity();
  const Vec3 a0 = x + e0, a1 = x + e1;
  Face f;
  double bound = std::numeric_limits<double>::infinity();
  if (std::find(candidates.begin(), candidates.end(), hint) != candidates.end() &&
      face_of(hint, positions, triangles, side, f))
    bound = closest_points_segment_triangle(a0, a1, f.a, f.b, f.c).distance;
  for (const std::int32_t t : candidates) {
    if (!corners_of(t, positions, triangles, f)) continue;
    const Vec3 centre = (f.a + f.b + f.c) / 3.0;
    const double radius = std::sqrt(std::max({(f.a - centre).squaredNorm(), (f.b - centre).squaredNorm(),
                                              (f.c - centre).squaredNorm()}));
    if ((closest_point_on_segment(centre, a0, a1).point - centre).norm() - radius >
        std::min(best.pair.distance, bound) + kSlack)
      continue;
    if (!orient(f, side)) continue;  // degenerate or not finite
    const SegmentTrianglePair p = closest_points_segment_triangle(a0, a1, f.a, f.b, f.c);
    if (p.distance < best.pair.distance) {
      best.triangle = t;
      best.face = f;
      best.pair = p;
    }
  }
  return best;
}

void require_proxy(bool ok, const char* key, double value, const char* what) {
  if (!ok) throw InputError(fmt::format("fabric proxy: {} must be {}, got {}", key, what, value));
}

}  // namespace

void validate(const FabricProxyParams& p) {
  validate(p.finger, "fabric proxy: finger");
  const auto non_negative = [](double v) { return std::isfinite(v) && v >= 0.0; };
  require_proxy(p.side == 1 || p.side == -1, "side", p.side, "+1 (front) or -1 (back)");
  require_proxy(std::isfinite(p.stiffness) && p.stiffness > 0.0, "stiffness", p.stiffness, "positive and finite");
  require_proxy(non_negative(p.static_friction), "static_friction", p.static_friction, "finite and not negative");
  require_proxy(non_negative(p.kinetic_friction) && p.kinetic_friction <= p.static_friction, "kinetic_friction",
                p.kinetic_friction, "finite, not negative and at most static_friction");
  require_proxy(non_negative(p.mass), "mass", p.mass, "finite and not negative");
  require_proxy(non_negative(p.damping), "damping", p.damping, "finite and not negative");
  require_proxy(std::isfinite(p.tolerance) && p.tolerance > 0.0, "tolerance", p.tolerance, "positive and finite");
}

FabricProxyState make_fabric_proxy_state(const Vec3& finger_position) {
  FabricProxyState s;
  s.position = finger_position;
  return s;
}

FabricProxy::FabricProxy(const FabricProxyParams& params) : params_(params) { validate(params); }

FabricProxyResult FabricProxy::update(FabricProxyState& state, const Pose& finger, std::span<const Vec3> positions,
                                      std::span<const mesh::Triangle> triangles,
                                      std::span<const std::int32_t> candidates, double dt) const noexcept {
  FabricProxyResult out;
  if (!finite_pose(finger) || !std::isfinite(dt) || !(dt > 0.0) || !state.position.allFinite() ||
      !state.velocity.allFinite()) {
    out.input_rejected = true;
    out.proxy = state.position;
    return out;
  }
  const FabricProxyParams& p = params_;
  const double r = p.finger.radius;
  const double k = p.stiffness;
  const Quat q = finger.orientation.normalized();
  const Vec3 e0 = q * p.finger.base, e1 = q * p.finger.tip;  // the axis, from the pose origin
  const Vec3 xd = finger.position;
  Vec3 x = state.position;

  const auto release = [&] {
    state = make_fabric_proxy_state(xd);
    out.proxy = xd;
    return out;
  };

  bool new_contact = false;
  bool carried = false;  // the fabric moved under the resting proxy since the last frame
  if (!state.in_contact) {
    // Free: the proxy was at the last device position. Sweep it toward the new one (a
    // translation) and stop at the first face it meets from its own side.
    double first = std::numeric_limits<double>::infinity();
    Vec3 landing = xd;
    Face f;
    for (const std::int32_t t : candidates) {
      if (!face_of(t, positions, triangles, p.side, f)) continue;
      const double h = plane_offset(f, e0, e1, r);
      const double g0 = f.normal.dot(x) - h, g1 = f.normal.dot(xd) - h;
      // Started behind the sheet itself (the axis on the other side: a finger that came round
      // from the wrong side passes), or ends in front: no touch. A start already closer than
      // the radius, on its own side, touches at once (a sheet that moved into the finger).
      if (g0 + r < -p.tolerance || !(g1 < 0.0)) continue;
      const double tau = g0 > 0.0 ? g0 / (g0 - g1) : 0.0;
      if (!(tau < first)) continue;
      const Vec3 at = x + tau * (xd - x);
      // Touching this face, not only its plane: the capsule's footprint is on the triangle.
      if (closest_points_segment_triangle(at + e0, at + e1, f.a, f.b, f.c).distance > r + 10.0 * p.tolerance)
        continue;
      first = tau;
      landing = at;
    }
    if (!std::isfinite(first)) return release();
    x = landing;
    new_contact = true;
    state.velocity = Vec3::Zero();
    state.friction = FrictionState::stick;  // first touch: held where it landed, unless pulled off at once
  } else {
    // Resting on moving fabric: carried with the material point it rests on.
    Face f;
    if (face_of(state.triangle, positions, triangles, p.side, f)) {
      const Vec3 motion = material_point(f, state.barycentric) - state.surface_point;
      x += motion;
      carried = motion.squaredNorm() > 0.0;
    }
  }

  // The face under the proxy, and the proxy put on its plane (pushed out if the fabric
  // moved into it, lowered if the device still presses).
  Nearest under = nearest_face(x, e0, e1, positions, triangles, candidates, p.side, state.triangle);
  if (under.triangle < 0) return release();
  double h = plane_offset(under.face, e0, e1, r);
  x += (h - under.face.normal.dot(x)) * under.face.normal;
  const Nearest settled = nearest_face(x, e0, e1, positions, triangles, candidates, p.side, under.triangle);
  if (settled.triangle < 0 || settled.pair.distance > r + 10.0 * p.tolerance) return release();  // slid off
  if (settled.triangle != under.triangle) {
    under = settled;
    h = plane_offset(under.face, e0, e1, r);
    x += (h - under.face.normal.dot(x)) * under.face.normal;
  }
  const Vec3 n = under.face.normal;
  const double depth = h - n.dot(xd);
  if (!(depth > 0.0)) return release();  // the device is back in front of the fabric

  // Friction. x_free is the frictionless proxy, the device pushed back onto the plane.
  const Vec3 x_free = xd + depth * n;
  const double fn = k * depth;
  const double ft = k * (x - x_free).norm();
  const double mu =
      !new_contact && state.friction == FrictionState::slip ? p.kinetic_friction : p.static_friction;
  FrictionState friction = FrictionState::stick;
  Vec3 v = Vec3::Zero();
  if (carried && ft > p.static_friction * fn) {
    // The fabric slid under the proxy past the friction cone (a stretched sheet let go springs
    // back at metres a second): the proxy slips on it and pulls with μ_k·F^N, as Coulomb's law
    // has it. Carried on with the fabric and then slid back by its own dynamics, it ended
    // millimetres off the finger, lost the sheet and found it again every other frame.
    friction = FrictionState::slip;
    x = x_free + (p.kinetic_friction * fn / ft) * (x - x_free);
  } else if (ft > mu * fn) {
    friction = FrictionState::slip;
    // m·(v − u) = dt·(k·(x_free − x_new) − b·v − μ_k·F^N·v/|v|), x_new = x + dt·v: backward
    // Euler in the spring and the damping. The spring and the damping act the same way in
    // every direction of the plane, so v is along v* (the step without friction), and
    // friction only shortens it, or stops the proxy if it cannot overcome it.
    const Vec3 u = state.velocity - state.velocity.dot(n) * n;
    const double a = p.mass + p.damping * dt + k * dt * dt;
    const Vec3 v_star = (p.mass * u + dt * k * (x_free - x)) / a;
    const double stop = dt * p.kinetic_friction * fn / a;
    const double speed = v_star.norm();
    if (speed > stop) v = (1.0 - stop / speed) * v_star;
    x += dt * v;
    // On curved fabric the slide may reach another face: keep on its front.
    const Nearest after = nearest_face(x, e0, e1, positions, triangles, candidates, p.side, under.triangle);
    if (after.triangle >= 0 && after.triangle != under.triangle) {
      const double h_after = plane_offset(after.face, e0, e1, r);
      const double below = h_after - after.face.normal.dot(x);
      if (below > 0.0) x += below * after.face.normal;
    }
  }

  const Nearest contact = nearest_face(x, e0, e1, positions, triangles, candidates, p.side, under.triangle);
  const Nearest& touched = contact.triangle >= 0 ? contact : under;
  out.in_contact = true;
  out.friction = friction;
  out.force = k * (x - xd);
  out.normal_force = out.force.dot(n);
  out.tangential_force = (out.force - out.normal_force * n).norm();
  out.depth = depth;
  out.proxy = x;
  out.contact_point = material_point(touched.face, touched.pair.barycentric);
  out.contact_normal = n;
  out.triangle = touched.triangle;
  out.barycentric = touched.pair.barycentric;
  out.vertices = touched.face.vertices;
  for (std::size_t i = 0; i < 3; ++i)
    out.vertex_loads[i] = -touched.pair.barycentric[static_cast<Eigen::Index>(i)] * out.force;

  state.position = x;
  state.velocity = v;
  state.in_contact = true;
  state.friction = friction;
  state.triangle = touched.triangle;
  state.barycentric = touched.pair.barycentric;
  state.surface_point = out.contact_point;
  return out;
}

}  // namespace tactus::contact
