#include "physics/nodules.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace tactus::physics {
namespace {

bool node_fixed(const std::vector<std::uint8_t>& fixed_dofs, Eigen::Index node) {
  const auto i = static_cast<std::size_t>(3 * node);
  return i + 2 < fixed_dofs.size() && (fixed_dofs[i] || fixed_dofs[i + 1] || fixed_dofs[i + 2]);
}

/// Unit vector from c to p; +z when p sits on c.
Vec3 outward(const Vec3& p, const Vec3& c, double& distance) {
  const Vec3 d = p - c;
  distance = d.norm();
  return distance > 0.0 ? Vec3(d / distance) : Vec3::UnitZ();
}

/// Where a node that moved from `start` to `end` this step is in contact with a sphere: the
/// contact normal and how deep it is (along that normal). The paper's radial projection of
/// the end point when it is inside; but a node that came from outside and crossed the
/// sphere (a fast step tunnelling through it, or past its centre) keeps the normal of the
/// point where it entered, with the depth its path reached. False: no contact.
bool contact_of(const Vec3& start, const Vec3& end, const Vec3& center, double radius, Vec3& normal, double& depth) {
  const double r2 = radius * radius;
  const bool end_inside = (end - center).squaredNorm() < r2;
  const Vec3 path = end - start;
  const double a = path.squaredNorm();
  const double c = (start - center).squaredNorm() - r2;
  Vec3 entry_normal;
  bool entered = false;
  if (c > 0.0 && a > 0.0) {
    const double b = 2.0 * path.dot(start - center);
    const double disc = b * b - 4.0 * a * c;
    const double t = disc >= 0.0 ? (-b - std::sqrt(disc)) / (2.0 * a) : -1.0;
    if (t >= 0.0 && t <= 1.0) {
      entered = true;
      entry_normal = (start + t * path - center) / radius;
    }
  }
  double distance = 0.0;
  if (end_inside) {
    normal = outward(end, center, distance);
    depth = radius - distance;
    if (!entered || normal.dot(entry_normal) > 0.0) return true;
  } else if (!entered) {
    return false;
  }
  const double s = std::clamp((center - start).dot(path) / a, 0.0, 1.0);
  normal = entry_normal;
  depth = std::max(radius - (start + s * path - center).norm(), 0.0);
  return true;
}

}  // namespace

Vec3 project_onto_sphere(const Vec3& p, const Vec3& center, double radius) {
  double distance = 0.0;
  const Vec3 n = outward(p, center, distance);
  return center + radius * n;
}

double hertz_pressure_coefficient(double young_modulus, double poisson_ratio, double radius) {
  const double contact_modulus = young_modulus / (1.0 - poisson_ratio * poisson_ratio);
  return contact_modulus / (std::numbers::pi * std::sqrt(radius));
}

void enforce_nodules(const NoduleSet& set, const std::vector<std::uint8_t>& fixed_dofs, const VecX& mass, double dt,
                     VecX& x, VecX& v) {
  if (set.nodules.empty()) return;
  const Eigen::Index nodes = x.size() / 3;
  for (const Nodule& nodule : set.nodules) {
    for (Eigen::Index i = 0; i < nodes; ++i) {
      auto p = x.segment<3>(3 * i);
      auto u = v.segment<3>(3 * i);
      // Symplectic and implicit Euler end a step with x = x_start + dt·v.
      Vec3 n;
      double overlap = 0.0;
      if (!contact_of(p - dt * u, p, nodule.center, nodule.radius, n, overlap) || node_fixed(fixed_dofs, i)) continue;
      p = nodule.center + (nodule.radius - overlap) * n;
      const double m = mass.size() > 3 * i ? mass[3 * i] : 0.0;
      const double area = static_cast<std::size_t>(i) < set.node_area.size() ? set.node_area[static_cast<std::size_t>(i)] : 0.0;
      if (nodule.rigid || !(m > 0.0) || !(dt > 0.0)) {
        p = nodule.center + nodule.radius * n;
        const double inward = u.dot(n);
        if (inward < 0.0) u -= inward * n;
        continue;
      }
      if (!(overlap > 0.0)) continue;
      // δ⁺ + c·√δ⁺ = δ with c = dt²·A·β/m; √δ⁺ is the positive root, written without the
      // cancellation of (−c + √(c² + 4δ))/2 when the nodule is stiff.
      const double c = dt * dt * area * nodule.pressure_coefficient / m;
      const double root = 2.0 * overlap / (c + std::sqrt(c * c + 4.0 * overlap));
      const double moved = overlap - root * root;
      p += moved * n;
      u += (moved / dt) * n;
    }
  }
}

int push_out_of_sphere(const Vec3& center, double radius, const Vec3& velocity,
                       const std::vector<std::uint8_t>& fixed_dofs, VecX& x, VecX& v) {
  const double r2 = radius * radius;
  const Eigen::Index nodes = x.size() / 3;
  int moved = 0;
  for (Eigen::Index i = 0; i < nodes; ++i) {
    auto p = x.segment<3>(3 * i);
    if ((p - center).squaredNorm() >= r2 || node_fixed(fixed_dofs, i)) continue;
    double distance = 0.0;
    const Vec3 n = outward(p, center, distance);
    p = center + radius * n;
    auto u = v.segment<3>(3 * i);
    // Only the normal velocity changes, and only up to the sphere's: it pushes, never pulls,
    // and leaves the tangential motion alone (no friction, no drag).
    const double behind = velocity.dot(n) - u.dot(n);
    if (behind > 0.0) u += behind * n;
    ++moved;
  }
  return moved;
}

}  // namespace tactus::physics
