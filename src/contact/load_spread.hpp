#pragma once
// How a contact force is shared among the surface vertices it acts on. A single point load
// on one triangle dents that triangle's corners only; the closest point then moves to the
// neighbouring triangle, which is now higher, and the load with it: on a mesh coarser than
// the contact the load flips between triangles every step and the force turns sideways. A
// real fingertip presses a disc of radius a (Hertz: a = √(R·d)) with the pressure
// p(ρ) = p0·√(1 − ρ²/a²), so the load is spread that way over the vertices near the contact
// point, each weighted by its share of the surface. On a mesh coarser than the disc the
// disc widens to the contact triangle's longest edge, so that the weights vary continuously
// as the contact point moves and at least one corner always carries the load.
#include <cstdint>
#include <span>
#include <vector>

#include "core/math.hpp"
#include "mesh/tri_mesh.hpp"

namespace tactus::contact {

/// One vertex's share of a spread contact load (shares sum to 1).
struct LoadShare {
  std::int32_t vertex = -1;
  double share = 0.0;
};

/// Each vertex's share of the surface area: a third of the area of each triangle around it.
[[nodiscard]] std::vector<double> vertex_areas(std::span<const Vec3> positions, std::span<const mesh::Triangle> triangles);

/// Contact radius of a sphere of radius R pressed to depth d into a flat surface: √(R·d)
/// (Hertz; 0 for a point or no depth) [m].
[[nodiscard]] double sphere_contact_radius(double sphere_radius, double depth);

/// The shares of the vertices within the spread radius of `point`, where `triangle` is the
/// surface triangle the point lies on and `contact_radius` the contact disc's radius.
/// Fills `out` up to its size, the nearest vertices first
/// when more qualify, and returns how many it wrote; shares are renormalised over them.
/// A negative `contact_radius` asks for the triangle's corners by barycentric weights only,
/// as does a neighbourhood without area. Allocation free.
int spread_load(std::span<const Vec3> positions, std::span<const mesh::Triangle> triangles,
                std::span<const double> areas, std::int32_t triangle, const Vec3& barycentric,
                double contact_radius, std::span<LoadShare> out);

}  // namespace tactus::contact
