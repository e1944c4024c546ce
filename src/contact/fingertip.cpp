#include "contact/fingertip.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include <fmt/format.h>

#include "contact/closest_point.hpp"
#include "core/error.hpp"

namespace tactus::contact {
namespace {

bool finite(const Vec3& v) { return v.allFinite(); }

/// A unit vector across `axis`, chosen the same way every time (axis need not be unit).
Vec3 across(const Vec3& axis) {
  const double len = axis.norm();
  if (!(len > 0.0)) return Vec3::UnitX();
  const Vec3 u = axis / len;
  // Cross with the world axis least aligned with u: never near-parallel.
  const Vec3 helper = std::abs(u.x()) <= std::abs(u.y()) && std::abs(u.x()) <= std::abs(u.z()) ? Vec3::UnitX()
                      : std::abs(u.y()) <= std::abs(u.z())                                    ? Vec3::UnitY()
                                                                                              : Vec3::UnitZ();
  return u.cross(helper).normalized();
}

/// Parallel below this sin² of the angle between segments (about 1e-6 rad).
constexpr double kParallelSine2 = 1e-12;

}  // namespace

void validate(const CapsuleShape& shape, const char* who) {
  if (!finite(shape.base) || !finite(shape.tip))
    throw InputError(fmt::format("{}: the capsule's base and tip must be finite", who));
  if (!(std::isfinite(shape.radius) && shape.radius > 0.0))
    throw InputError(fmt::format("{}: the capsule radius must be positive and finite, got {} m", who, shape.radius));
  const Vec3 axis = shape.tip - shape.base;
  const double len = axis.norm();
  const double pad = shape.pad_normal.norm();
  const Vec3 across_axis =
      len > 0.0 ? Vec3(shape.pad_normal - shape.pad_normal.dot(axis / len) * axis / len) : shape.pad_normal;
  // The pad plane needs a direction across the axis; a normal along it names none.
  if (!finite(shape.pad_normal) || !(pad > 0.0) || !(across_axis.norm() > 1e-6 * pad))
    throw InputError(
        fmt::format("{}: the pad normal must be finite, non-zero and not along the axis base -> tip", who));
}

Capsule posed(const CapsuleShape& shape, const Pose& pose) noexcept {
  return {pose.to_world(shape.base), pose.to_world(shape.tip), shape.radius};
}

Vec3 pad_normal(const CapsuleShape& shape, const Pose& pose) noexcept {
  const Vec3 axis = shape.tip - shape.base;
  const double len = axis.norm();
  Vec3 n = shape.pad_normal;
  if (len > 0.0) n -= n.dot(axis / len) * axis / len;
  const double n_len = n.norm();
  n = n_len > 0.0 ? Vec3(n / n_len) : across(axis);
  return pose.orientation * n;
}

SegmentPoint closest_point_on_segment(const Vec3& p, const Vec3& a, const Vec3& b) noexcept {
  const Vec3 d = b - a;
  const double len2 = d.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((p - a).dot(d) / len2, 0.0, 1.0) : 0.0;
  return {t, a + t * d};
}

SegmentPair closest_points_segments(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1) noexcept {
  const Vec3 d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  double s = 0.0, t = 0.0;
  if (!(a > 0.0) && !(e > 0.0)) {
    s = t = 0.0;
  } else if (!(a > 0.0)) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (!(e > 0.0)) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2);
      const double denom = a * e - b * b;
      if (denom > kParallelSine2 * a * e) {
        s = std::clamp((b * f - c * e) / denom, 0.0, 1.0);
        t = (b * s + f) / e;
        if (t < 0.0) {
          t = 0.0;
          s = std::clamp(-c / a, 0.0, 1.0);
        } else if (t > 1.0) {
          t = 1.0;
          s = std::clamp((b - c) / a, 0.0, 1.0);
        }
      } else {
        // Parallel: q0 and q1 projected onto the first segment bound the overlap; take
        // its middle (or the nearest ends when the projections do not overlap).
        const double s0 = (q0 - p0).dot(d1) / a, s1 = (q1 - p0).dot(d1) / a;
        const double lo = std::max(0.0, std::min(s0, s1)), hi = std::min(1.0, std::max(s0, s1));
        s = lo <= hi ? 0.5 * (lo + hi) : (std::max(s0, s1) < 0.0 ? 0.0 : 1.0);
        t = std::clamp((p0 + s * d1 - q0).dot(d2) / e, 0.0, 1.0);
        s = std::clamp((q0 + t * d2 - p0).dot(d1) / a, 0.0, 1.0);
      }
    }
  }
  SegmentPair out;
  out.s = s;
  out.t = t;
  out.on_first = p0 + s * d1;
  out.on_second = q0 + t * d2;
  out.distance = (out.on_second - out.on_first).norm();
  return out;
}

SegmentTrianglePair closest_points_segment_triangle(const Vec3& p0, const Vec3& p1, const Vec3& a, const Vec3& b,
                                                    const Vec3& c) noexcept {
  SegmentTrianglePair best;
  double best_d2 = std::numeric_limits<double>::infinity();
  const auto consider = [&](double t, const Vec3& on_segment, const Vec3& on_triangle, const Vec3& bary) {
    const double d2 = (on_triangle - on_segment).squaredNorm();
    if (d2 < best_d2) {
      best_d2 = d2;
      best.t = t;
      best.on_segment = on_segment;
      best.on_triangle = on_triangle;
      best.barycentric = bary;
    }
  };

  // The segment piercing the face.
  const Vec3 n = (b - a).cross(c - a);
  const double h0 = n.dot(p0 - a), h1 = n.dot(p1 - a);
  if (n.squaredNorm() > 0.0 && ((h0 <= 0.0 && h1 >= 0.0) || (h0 >= 0.0 && h1 <= 0.0)) && h0 != h1) {
    const double t = h0 / (h0 - h1);
    const Vec3 x = p0 + t * (p1 - p0);
    const TrianglePoint q = closest_point_on_triangle(x, a, b, c);
    consider(t, x, q.point, q.barycentric);
  }
  // End points against the face.
  const TrianglePoint q0 = closest_point_on_triangle(p0, a, b, c);
  consider(0.0, p0, q0.point, q0.barycentric);
  const TrianglePoint q1 = closest_point_on_triangle(p1, a, b, c);
  consider(1.0, p1, q1.point, q1.barycentric);
  // The segment against each edge.
  const SegmentPair ab = closest_points_segments(p0, p1, a, b);
  consider(ab.s, ab.on_first, ab.on_second, Vec3(1.0 - ab.t, ab.t, 0.0));
  const SegmentPair bc = closest_points_segments(p0, p1, b, c);
  consider(bc.s, bc.on_first, bc.on_second, Vec3(0.0, 1.0 - bc.t, bc.t));
  const SegmentPair ca = closest_points_segments(p0, p1, c, a);
  consider(ca.s, ca.on_first, ca.on_second, Vec3(ca.t, 0.0, 1.0 - ca.t));
  best.distance = std::sqrt(best_d2);
  return best;
}

CapsulePoint point_capsule(const Vec3& p, const Capsule& capsule) noexcept {
  const SegmentPoint axis = closest_point_on_segment(p, capsule.base, capsule.tip);
  const Vec3 d = p - axis.point;
  const double dist = d.norm();
  CapsulePoint out;
  out.axis_t = axis.t;
  out.normal = dist > 0.0 ? Vec3(d / dist) : across(capsule.tip - capsule.base);
  out.surface_point = axis.point + capsule.radius * out.normal;
  out.signed_distance = dist - capsule.radius;
  return out;
}

CapsulePair capsule_capsule(const Capsule& first, const Capsule& second) noexcept {
  const SegmentPair axes = closest_points_segments(first.base, first.tip, second.base, second.tip);
  const Vec3 d = axes.on_second - axes.on_first;
  CapsulePair out;
  out.s = axes.s;
  out.t = axes.t;
  if (axes.distance > 0.0) {
    out.normal = d / axes.distance;
  } else {
    // Crossing axes: across both (or across the first when they are parallel).
    const Vec3 both = (first.tip - first.base).cross(second.tip - second.base);
    out.normal = both.norm() > 0.0 ? Vec3(both.normalized()) : across(first.tip - first.base);
  }
  out.on_first = axes.on_first + first.radius * out.normal;
  out.on_second = axes.on_second - second.radius * out.normal;
  out.signed_distance = axes.distance - first.radius - second.radius;
  return out;
}

ParticleSweep sweep_particle_capsule(const Vec3& p0, const Vec3& p1, const CapsuleShape& shape, const Pose& pose0,
                                     const Pose& pose1, const SweepOptions& options) noexcept {
  ParticleSweep out;
  out.particle = p1;
  const Quat q0 = pose0.orientation.normalized();
  Quat q1 = pose1.orientation.normalized();
  if (q0.dot(q1) < 0.0) q1.coeffs() = -q1.coeffs();  // the short way round, as slerp takes it
  const auto at = [&](double t) {
    Pose pose;
    pose.position = (1.0 - t) * pose0.position + t * pose1.position;
    pose.orientation = q0.slerp(t, q1);
    const Vec3 p = (1.0 - t) * p0 + t * p1;
    return std::pair{p, point_capsule(p, posed(shape, pose))};
  };

  const Quat relative = q0.conjugate() * q1;
  const double angle = 2.0 * std::atan2(relative.vec().norm(), std::abs(relative.w()));
  const double lever = std::max(shape.base.norm(), shape.tip.norm());
  const double bound = (p1 - p0).norm() + (pose1.position - pose0.position).norm() + angle * lever;
  const double tolerance = std::max(options.tolerance, 0.0);

  double t = 0.0;
  for (int i = 0; i < options.max_iterations; ++i) {
    const auto [p, q] = at(t);
    out.iterations = i + 1;
    if (!std::isfinite(q.signed_distance)) return out;  // non-finite input: no claim of a hit
    if (q.signed_distance <= tolerance) {
      out.hit = true;
      out.time = t;
      out.particle = p;
      out.normal = q.normal;
      out.signed_distance = q.signed_distance;
      return out;
    }
    if (!(bound > 0.0)) return out;  // nothing moves
    t += q.signed_distance / bound;
    if (t > 1.0) return out;
  }
  // Out of iterations in a long graze: report the last time known to be free, as a hit.
  const auto [p, q] = at(t);
  out.hit = true;
  out.converged = false;
  out.time = t;
  out.particle = p;
  out.normal = q.normal;
  out.signed_distance = q.signed_distance;
  return out;
}

}  // namespace tactus::contact
