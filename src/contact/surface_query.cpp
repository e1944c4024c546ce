#include "contact/surface_query.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <fmt/format.h>

#include "core/error.hpp"

namespace tactus::contact {
namespace {

/// A sweep's time of first contact when there is none.
constexpr double kNever = std::numeric_limits<double>::infinity();

// A contact found by the face test counts as inside the face this far outside it (in
// barycentric units), so that a touch exactly on an edge is never lost between the face test
// and the edge test to rounding. Finding a contact slightly early is safe; missing one is not.
constexpr double kFaceTolerance = 1e-9;

/// Earliest t in [0, 1] at which from + t·d is at distance `radius` from the point v, moving
/// toward it; +inf when never. The start is known to be farther than `radius`.
double sweep_point(const Vec3& from, const Vec3& d, double radius, const Vec3& v) {
  const Vec3 m = from - v;
  const double b = m.dot(d);
  if (!(b < 0.0)) return kNever;  // moving away or parallel
  const double a = d.squaredNorm();
  const double c = m.squaredNorm() - radius * radius;
  if (c <= 0.0) return 0.0;
  const double disc = b * b - a * c;
  if (disc < 0.0) return kNever;
  // The smaller root as c / (−b + √disc): no cancellation since b < 0.
  const double t = c / (-b + std::sqrt(disc));
  return t <= 1.0 ? t : kNever;
}

/// Earliest t in [0, 1] at which from + t·d is at distance `radius` from the segment
/// (p0, p1) through its interior (the cylinder around it); the end points are left to
/// sweep_point. +inf when never.
double sweep_edge(const Vec3& from, const Vec3& d, double radius, const Vec3& p0, const Vec3& p1) {
  const Vec3 e = p1 - p0;
  const double len2 = e.squaredNorm();
  if (!(len2 > 0.0)) return kNever;
  const Vec3 m = from - p0;
  // Distances to the axis times |e|: |m×e| at the start, |d×e| per unit t.
  const Vec3 me = m.cross(e), de = d.cross(e);
  const double a = de.squaredNorm();
  const double b = me.dot(de);
  if (!(b < 0.0) || !(a > 0.0)) return kNever;  // moving away from the axis, or along it
  const double c = me.squaredNorm() - radius * radius * len2;
  if (c <= 0.0) return kNever;  // already within the infinite cylinder: an end sphere comes first
  const double disc = b * b - a * c;
  if (disc < 0.0) return kNever;
  const double t = c / (-b + std::sqrt(disc));
  if (t > 1.0) return kNever;
  const double u = (m + t * d).dot(e);
  return (u >= 0.0 && u <= len2) ? t : kNever;
}

/// Barycentric coordinates of q (assumed in the plane) in triangle (a, b, c) with
/// unnormalised normal n = (b − a)×(c − a).
Vec3 barycentric_in_plane(const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& n) {
  const double inv = 1.0 / n.squaredNorm();
  const double wa = n.dot((c - b).cross(q - b)) * inv;
  const double wb = n.dot((a - c).cross(q - c)) * inv;
  return {wa, wb, 1.0 - wa - wb};
}

/// Angle at vertex v between the directions to p and q.
double corner_angle(const Vec3& v, const Vec3& p, const Vec3& q) {
  const Vec3 e0 = p - v, e1 = q - v;
  return std::atan2(e0.cross(e1).norm(), e0.dot(e1));
}

bool boxes_overlap(const Vec3& lo0, const Vec3& hi0, const Vec3& lo1, const Vec3& hi1) {
  return (lo0.array() <= hi1.array()).all() && (lo1.array() <= hi0.array()).all();
}

}  // namespace

SweepHit sweep_sphere_triangle(const Vec3& from, const Vec3& to, double radius, const Vec3& a, const Vec3& b,
                               const Vec3& c) {
  SweepHit hit;
  const Vec3 d = to - from;
  const Vec3 n_raw = (b - a).cross(c - a);
  const double n_len = n_raw.norm();
  const Vec3 face_normal = n_len > 0.0 ? Vec3(n_raw / n_len) : Vec3::Zero();

  const TrianglePoint start = closest_point_on_triangle(from, a, b, c);
  const Vec3 away = from - start.point;
  const double start_distance = away.norm();
  if (start_distance <= radius) {
    // Overlapping already. The distance along the segment is convex in t, so if it does not
    // decrease at t = 0 it never does: only an approaching sphere is stopped.
    Vec3 out = start_distance > 0.0 ? Vec3(away / start_distance) : Vec3(face_normal);
    if (start_distance == 0.0 && d.dot(out) > 0.0) out = -out;
    if (!(d.dot(out) < 0.0)) return hit;
    hit.hit = true;
    hit.time = 0.0;
    hit.center = from;
    hit.point = start.point;
    hit.barycentric = start.barycentric;
    hit.normal = out;
    return hit;
  }

  double best = kNever;
  if (n_len > 0.0) {
    // Entry into the slab |n·(x − a)| ≤ radius from either side; the face interior can only
    // be touched first at that instant.
    const double s0 = face_normal.dot(from - a), s1 = face_normal.dot(to - a);
    double t = kNever, side = 1.0;
    if (s0 > radius && s1 < radius) {
      t = (s0 - radius) / (s0 - s1);
    } else if (s0 < -radius && s1 > -radius) {
      t = (-radius - s0) / (s1 - s0);
      side = -1.0;
    }
    if (t <= 1.0) {
      const Vec3 q = from + t * d - side * radius * face_normal;
      if (barycentric_in_plane(q, a, b, c, n_raw).minCoeff() >= -kFaceTolerance) best = t;
    }
  }
  best = std::min({best, sweep_edge(from, d, radius, a, b), sweep_edge(from, d, radius, b, c),
                   sweep_edge(from, d, radius, c, a)});
  best = std::min({best, sweep_point(from, d, radius, a), sweep_point(from, d, radius, b),
                   sweep_point(from, d, radius, c)});
  if (!(best <= 1.0)) return hit;

  hit.hit = true;
  hit.time = std::clamp(best, 0.0, 1.0);
  hit.center = from + hit.time * d;
  const TrianglePoint contact = closest_point_on_triangle(hit.center, a, b, c);
  hit.point = contact.point;
  hit.barycentric = contact.barycentric;
  const Vec3 gap = hit.center - contact.point;
  const double gap_len = gap.norm();
  if (radius > 0.0 && gap_len > 0.5 * radius) {
    hit.normal = gap / gap_len;
  } else {
    // Radius zero: the segment met the surface, and the gap is rounding; face the motion.
    hit.normal = face_normal.dot(d) > 0.0 ? Vec3(-face_normal) : face_normal;
    if (hit.normal.squaredNorm() == 0.0) hit.normal = -d.normalized();
  }
  return hit;
}

double pseudo_normal_weight(const Vec3& barycentric, const Vec3& a, const Vec3& b, const Vec3& c) {
  const int zeros = (barycentric.array() == 0.0).count();
  if (zeros == 0) return 2.0 * std::numbers::pi;
  if (zeros == 1) return std::numbers::pi;
  if (barycentric[0] != 0.0) return corner_angle(a, b, c);
  if (barycentric[1] != 0.0) return corner_angle(b, c, a);
  return corner_angle(c, a, b);
}

BruteForceSurfaceQuery::BruteForceSurfaceQuery(std::span<const Vec3> positions,
                                               std::span<const mesh::Triangle> triangles)
    : positions_(positions), triangles_(triangles) {
  if (triangles.size() > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()))
    throw InputError(fmt::format("surface query: {} triangles is more than supported", triangles.size()));
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (const mesh::Index v : triangles[t])
      if (v < 0 || static_cast<std::size_t>(v) >= positions.size())
        throw InputError(fmt::format("surface query: triangle {} refers to vertex {}, but there are {} vertices", t,
                                     v, positions.size()));
}

std::optional<std::array<Vec3, 3>> BruteForceSurfaceQuery::triangle(std::int32_t t) const {
  if (t < 0 || static_cast<std::size_t>(t) >= triangles_.size()) return std::nullopt;
  const auto& tri = triangles_[static_cast<std::size_t>(t)];
  return std::array<Vec3, 3>{positions_[static_cast<std::size_t>(tri[0])],
                             positions_[static_cast<std::size_t>(tri[1])],
                             positions_[static_cast<std::size_t>(tri[2])]};
}

PseudoNormalSum::PseudoNormalSum(const Vec3& p, const SurfacePoint& closest)
    : p_(p),
      closest_(closest),
      on_edge_or_vertex_((closest.barycentric.array() == 0.0).any()),
      tolerance_(1e-10 * (1e-3 + closest.point.cwiseAbs().maxCoeff() + closest.distance)),
      lo_(closest.point.array() - tolerance_),
      hi_(closest.point.array() + tolerance_) {}

Vec3 PseudoNormalSum::term(const Vec3& a, const Vec3& b, const Vec3& c) const {
  if (!boxes_overlap(lo_, hi_, a.cwiseMin(b).cwiseMin(c), a.cwiseMax(b).cwiseMax(c))) return Vec3::Zero();
  const TrianglePoint q = closest_point_on_triangle(p_, a, b, c);
  if ((q.point - closest_.point).cwiseAbs().maxCoeff() > tolerance_) return Vec3::Zero();
  const Vec3 n_raw = (b - a).cross(c - a);
  const double n_len = n_raw.norm();
  if (!(n_len > 0.0)) return Vec3::Zero();
  return pseudo_normal_weight(q.barycentric, a, b, c) * n_raw / n_len;
}

ClosestSurfacePoint PseudoNormalSum::result(const Vec3& sum) const {
  ClosestSurfacePoint out;
  if (closest_.triangle < 0) return out;
  out.found = true;
  out.triangle = closest_.triangle;
  out.point = closest_.point;
  out.barycentric = closest_.barycentric;
  out.distance = closest_.distance;
  Vec3 normal = closest_.normal;
  if (on_edge_or_vertex_) {
    const double sum_len = sum.norm();
    if (sum_len > 0.0) normal = sum / sum_len;
  }
  if (normal.squaredNorm() == 0.0) normal = Vec3::UnitZ();  // only degenerate triangles
  out.normal = normal;
  out.behind = (p_ - closest_.point).dot(normal) < 0.0;
  return out;
}

ClosestSurfacePoint BruteForceSurfaceQuery::closest_point(const Vec3& p) const {
  const PseudoNormalSum side(p, closest_point_on_surface(p, positions_, triangles_));
  // On an edge or a vertex: the angle-weighted normal of every triangle sharing the point.
  Vec3 sum = Vec3::Zero();
  if (side.on_edge_or_vertex())
    for (const auto& tri : triangles_)
      sum += side.term(positions_[static_cast<std::size_t>(tri[0])], positions_[static_cast<std::size_t>(tri[1])],
                       positions_[static_cast<std::size_t>(tri[2])]);
  return side.result(sum);
}

SweepHit BruteForceSurfaceQuery::sweep_sphere(const Vec3& from, const Vec3& to, double radius) const {
  SweepHit best;
  const Vec3 lo = from.cwiseMin(to).array() - radius, hi = from.cwiseMax(to).array() + radius;
  for (std::size_t t = 0; t < triangles_.size(); ++t) {
    const auto& tri = triangles_[t];
    const Vec3& a = positions_[static_cast<std::size_t>(tri[0])];
    const Vec3& b = positions_[static_cast<std::size_t>(tri[1])];
    const Vec3& c = positions_[static_cast<std::size_t>(tri[2])];
    if (!boxes_overlap(lo, hi, a.cwiseMin(b).cwiseMin(c), a.cwiseMax(b).cwiseMax(c))) continue;
    SweepHit h = sweep_sphere_triangle(from, to, radius, a, b, c);
    if (h.hit && (!best.hit || h.time < best.time)) {
      best = h;
      best.triangle = static_cast<std::int32_t>(t);
    }
  }
  return best;
}

ClosestSurfacePoint HalfSpaceQuery::closest_point(const Vec3& p) const {
  ClosestSurfacePoint out;
  const double s = normal_.dot(p) - offset_;
  out.found = true;
  out.point = p - s * normal_;
  out.normal = normal_;
  out.distance = std::abs(s);
  out.behind = s < 0.0;
  return out;
}

SweepHit HalfSpaceQuery::sweep_sphere(const Vec3& from, const Vec3& to, double radius) const {
  SweepHit hit;
  const double s0 = normal_.dot(from) - offset_, s1 = normal_.dot(to) - offset_;
  if (!(s1 < s0) || !(s1 < radius)) return hit;  // moving away, along, or staying clear
  hit.hit = true;
  hit.time = s0 <= radius ? 0.0 : (s0 - radius) / (s0 - s1);
  hit.center = from + hit.time * (to - from);
  hit.point = hit.center - (normal_.dot(hit.center) - offset_) * normal_;
  hit.normal = normal_;
  return hit;
}

}  // namespace tactus::contact
