#include "compile/nodules.hpp"

namespace tactus::compile {

physics::NoduleSet physics_nodules(const scene::Body& body) {
  physics::NoduleSet set;
  if (body.nodules.empty()) return set;
  bool any_soft = false;
  for (const scene::Nodule& n : body.nodules) {
    physics::Nodule p;
    p.center = n.center;
    p.radius = n.radius;
    p.rigid = n.rigid;
    if (!n.rigid) {
      p.pressure_coefficient = physics::hertz_pressure_coefficient(n.young_modulus, n.poisson_ratio, n.radius);
      any_soft = true;
    }
    set.nodules.push_back(p);
  }
  if (any_soft) {
    // A third of each triangle's area to each of its corners (the sheet's simulation nodes
    // are its surface vertices).
    const mesh::TriMesh& s = body.surface;
    set.node_area.assign(s.vertices.size(), 0.0);
    for (const auto& t : s.triangles) {
      const Vec3& a = s.vertices[static_cast<std::size_t>(t[0])];
      const Vec3& b = s.vertices[static_cast<std::size_t>(t[1])];
      const Vec3& c = s.vertices[static_cast<std::size_t>(t[2])];
      const double third = (b - a).cross(c - a).norm() / 6.0;
      for (int k = 0; k < 3; ++k) set.node_area[static_cast<std::size_t>(t[static_cast<std::size_t>(k)])] += third;
    }
  }
  return set;
}

}  // namespace tactus::compile
