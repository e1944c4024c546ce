// CGAL's decimation and subdivision on the engine's TriMesh (the library's only CGAL
// translation unit).
//
// Decimation uses the Garland–Heckbert plane policies (cost: the sum of squared distances to
// the planes of the faces merged into a vertex; placement: the quadric's minimiser, the best
// point of the collapsed edge when the quadric is singular), which CGAL has had since 5.3:
// the classic quadric error metric that the level errors are judged by (distance to the
// surface), cheaper than Lindstrom–Turk's volume- and boundary-preserving terms, which a
// closed surface does not need. The placement is wrapped in Bounded_normal_change_placement
// so that no collapse turns a triangle over (a fold would break the outward orientation).
#include "lod/remesh.hpp"

#include <CGAL/Simple_cartesian.h>
#include <CGAL/Subdivision_method_3/subdivision_methods_3.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_simplification/Edge_collapse_visitor_base.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Bounded_normal_change_placement.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Count_stop_predicate.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/GarlandHeckbert_plane_policies.h>
#include <CGAL/Surface_mesh_simplification/edge_collapse.h>

#include <limits>
#include <stdexcept>
#include <vector>

namespace tactus::lod {
namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Point = Kernel::Point_3;
using Surface = CGAL::Surface_mesh<Point>;

Surface to_surface(const mesh::TriMesh& input) {
  Surface surface;
  std::vector<Surface::Vertex_index> vertices;
  vertices.reserve(input.vertices.size());
  for (const Vec3& p : input.vertices) vertices.push_back(surface.add_vertex(Point(p.x(), p.y(), p.z())));
  for (const mesh::Triangle& t : input.triangles) {
    const Surface::Face_index f = surface.add_face(vertices[static_cast<std::size_t>(t[0])],
                                                   vertices[static_cast<std::size_t>(t[1])],
                                                   vertices[static_cast<std::size_t>(t[2])]);
    // The caller checked the mesh is a closed oriented manifold, so every face goes in.
    if (f == Surface::null_face()) throw std::logic_error("lod: CGAL refused a triangle of a checked mesh");
  }
  return surface;
}

mesh::TriMesh to_tri_mesh(const Surface& surface) {
  mesh::TriMesh out;
  std::vector<mesh::Index> renumber(surface.num_vertices() + surface.number_of_removed_vertices(), -1);
  for (const Surface::Vertex_index v : surface.vertices()) {
    renumber[static_cast<std::size_t>(v)] = static_cast<mesh::Index>(out.vertices.size());
    const Point& p = surface.point(v);
    out.vertices.emplace_back(p.x(), p.y(), p.z());
  }
  for (const Surface::Face_index f : surface.faces()) {
    mesh::Triangle t{};
    int k = 0;
    for (const Surface::Vertex_index v : CGAL::vertices_around_face(surface.halfedge(f), surface)) {
      if (k == 3) throw std::logic_error("lod: CGAL returned a face with more than three vertices");
      t[static_cast<std::size_t>(k++)] = renumber[static_cast<std::size_t>(v)];
    }
    if (k != 3) throw std::logic_error("lod: CGAL returned a face with fewer than three vertices");
    out.triangles.push_back(t);
  }
  return out;
}

}  // namespace

mesh::TriMesh decimate(const mesh::TriMesh& input, std::size_t target_triangles) {
  namespace SMS = CGAL::Surface_mesh_simplification;
  Surface surface = to_surface(input);
  // A closed triangle mesh has 3F/2 edges, so the edge count CGAL stops at fixes the faces.
  const std::size_t target_edges = target_triangles * 3 / 2;
  SMS::Count_stop_predicate<Surface> stop(target_edges);
  using Policies = SMS::GarlandHeckbert_plane_policies<Surface, Kernel>;
  Policies policies(surface);
  const SMS::Bounded_normal_change_placement<Policies::Get_placement> placement(policies.get_placement());
  SMS::edge_collapse(surface, stop, CGAL::parameters::get_cost(policies.get_cost()).get_placement(placement));
  surface.collect_garbage();
  return to_tri_mesh(surface);
}

mesh::TriMesh loop_subdivide(const mesh::TriMesh& input) {
  Surface surface = to_surface(input);
  CGAL::Subdivision_method_3::Loop_subdivision(surface, CGAL::parameters::number_of_iterations(1));
  return to_tri_mesh(surface);
}

}  // namespace tactus::lod
