#include "core/hash.hpp"
#include "mesh/tet_mesh.hpp"
#include "mesh/tri_mesh.hpp"

namespace tactus::mesh {

Aabb TriMesh::bounds() const {
  Aabb box;
  for (const auto& v : vertices) box.add(v);
  return box;
}

Vec3 TriMesh::face_normal(std::size_t t) const {
  const auto& f = triangles[t];
  const Vec3 n = (vertices[f[1]] - vertices[f[0]]).cross(vertices[f[2]] - vertices[f[0]]);
  const double len = n.norm();
  return len > 0.0 ? Vec3(n / len) : Vec3::Zero();
}

std::uint64_t TriMesh::content_hash() const {
  Fnv1a h;
  h.add_value(vertices.size());
  h.add(vertices.data(), vertices.size() * sizeof(Vec3));
  h.add_value(triangles.size());
  h.add(triangles.data(), triangles.size() * sizeof(Triangle));
  return h.value();
}

double TriMesh::face_area(std::size_t t) const {
  const auto& f = triangles[t];
  return 0.5 * (vertices[f[1]] - vertices[f[0]]).cross(vertices[f[2]] - vertices[f[0]]).norm();
}

double TriMesh::area() const {
  double a = 0.0;
  for (std::size_t t = 0; t < triangles.size(); ++t) a += face_area(t);
  return a;
}

double TriMesh::signed_volume() const {
  double v = 0.0;
  for (const auto& f : triangles)
    v += vertices[f[0]].dot(vertices[f[1]].cross(vertices[f[2]]));
  return v / 6.0;
}

Aabb TetMesh::bounds() const {
  Aabb box;
  for (const auto& v : vertices) box.add(v);
  return box;
}

double TetMesh::tet_volume(std::size_t t) const {
  const auto& e = tets[t];
  return signed_tet_volume(vertices[e[0]], vertices[e[1]], vertices[e[2]], vertices[e[3]]);
}

double TetMesh::volume() const {
  double v = 0.0;
  for (std::size_t t = 0; t < tets.size(); ++t) v += tet_volume(t);
  return v;
}

}  // namespace tactus::mesh
