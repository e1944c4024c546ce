#include "mesh/half_edge.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <numbers>

#include "core/error.hpp"
#include "mesh/generators.hpp"
#include "small_meshes.hpp"

namespace tactus::mesh {
namespace {

using test::tetrahedron_surface;

void expect_consistent(const HalfEdgeMesh& he) {
  for (Index h = 0; h < static_cast<Index>(he.num_half_edges()); ++h) {
    EXPECT_EQ(he.twin(he.twin(h)), h);
    EXPECT_NE(he.twin(h), h);
    EXPECT_EQ(he.origin(he.twin(h)), he.target(h));
    EXPECT_EQ(he.target(he.twin(h)), he.origin(h));
  }
}

std::string error_of(const TriMesh& m) {
  try {
    HalfEdgeMesh he(m);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(HalfEdge, TetrahedronSurface) {
  const HalfEdgeMesh he(tetrahedron_surface());
  EXPECT_EQ(he.num_faces(), 4u);
  EXPECT_EQ(he.num_edges(), 6u);
  EXPECT_EQ(he.num_half_edges(), 12u);
  EXPECT_TRUE(he.closed());
  EXPECT_EQ(he.euler_characteristic(), 2);
  expect_consistent(he);
  for (Index v = 0; v < 4; ++v) {
    auto ring = he.one_ring(v);
    EXPECT_EQ(ring.size(), 3u);
    std::sort(ring.begin(), ring.end());
    EXPECT_EQ(std::adjacent_find(ring.begin(), ring.end()), ring.end());
    EXPECT_EQ(he.vertex_faces(v).size(), 3u);
    EXPECT_FALSE(he.is_boundary_vertex(v));
  }
  EXPECT_TRUE(he.boundary_loops().empty());
}

TEST(HalfEdge, CubeSurfaceOneRings) {
  const TriMesh box = box_surface(Vec3(1, 1, 1), 2);
  const HalfEdgeMesh he(box);
  EXPECT_EQ(he.euler_characteristic(), 2);
  EXPECT_TRUE(he.closed());
  expect_consistent(he);
  std::size_t ring_total = 0;
  for (Index v = 0; v < static_cast<Index>(he.num_vertices()); ++v) {
    const auto ring = he.one_ring(v);
    EXPECT_GE(ring.size(), 3u);
    ring_total += ring.size();
    // Each ring neighbour is one edge away.
    for (Index w : ring) EXPECT_LT((box.vertices[w] - box.vertices[v]).norm(), 0.75);
  }
  EXPECT_EQ(ring_total, he.num_half_edges());  // every half-edge leaves exactly one vertex
  EXPECT_GT(he.k_ring(0, 2).size(), he.k_ring(0, 1).size());
}

TEST(HalfEdge, FaceIterationMatchesTriangles) {
  const TriMesh m = sphere(1.0, 1);
  const HalfEdgeMesh he(m);
  for (Index f = 0; f < static_cast<Index>(he.num_faces()); ++f) {
    EXPECT_EQ(he.face_vertices(f), m.triangles[f]);
    for (Index h : he.face_half_edges(f)) EXPECT_EQ(he.face(h), f);
  }
}

TEST(HalfEdge, VertexNormalsPointOutwardOnSphere) {
  const TriMesh m = sphere(2.0, 2);
  const auto normals = HalfEdgeMesh(m).vertex_normals();
  for (std::size_t v = 0; v < m.vertices.size(); ++v) {
    EXPECT_NEAR(normals[v].norm(), 1.0, 1e-12);
    EXPECT_GT(normals[v].dot(m.vertices[v].normalized()), 0.99);
  }
}

TEST(HalfEdge, OpenPlateBoundaryLoop) {
  const TriMesh plate = grid_plate(1.0, 1.0, 3, 2);
  const HalfEdgeMesh he(plate);
  EXPECT_FALSE(he.closed());
  EXPECT_EQ(he.euler_characteristic(), 1);  // a disc
  expect_consistent(he);
  const auto loops = he.boundary_loops();
  ASSERT_EQ(loops.size(), 1u);
  EXPECT_EQ(loops[0].size(), 10u);  // 2·(3 + 2) boundary edges
  EXPECT_TRUE(he.is_boundary_vertex(0));
  // A corner vertex's walk covers its whole fan, boundary neighbours included.
  EXPECT_EQ(he.one_ring(0).size(), he.vertex_faces(0).size() + 1);
}

TEST(HalfEdge, RejectsEdgeSharedByThreeFaces) {
  TriMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
  m.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  const std::string what = error_of(m);
  EXPECT_NE(what.find("non-manifold edge (0, 1)"), std::string::npos) << what;
  EXPECT_NE(what.find("3 triangles (0, 1, 2)"), std::string::npos) << what;
}

TEST(HalfEdge, RejectsInconsistentOrientation) {
  TriMesh m = tetrahedron_surface();
  std::swap(m.triangles[3][1], m.triangles[3][2]);  // flip face 3: (1, 3, 2)
  const std::string what = error_of(m);
  EXPECT_NE(what.find("inconsistent orientation at edge"), std::string::npos) << what;
  EXPECT_NE(what.find("triangles"), std::string::npos) << what;
}

TEST(HalfEdge, RejectsBadIndexAndBowtie) {
  TriMesh m = tetrahedron_surface();
  m.triangles[2][1] = 9;
  EXPECT_NE(error_of(m).find("vertex index 9 out of range"), std::string::npos);

  TriMesh bowtie;  // two triangles touching at vertex 0 only
  bowtie.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}};
  bowtie.triangles = {{0, 1, 2}, {0, 3, 4}};
  EXPECT_NE(error_of(bowtie).find("non-manifold vertex 0"), std::string::npos) << error_of(bowtie);
}

}  // namespace
}  // namespace tactus::mesh
