// The local patch on its own: which nodes and triangles it takes, that the mass-spring patch
// settles where its springs balance the contact, that the implicit contact solve is stable
// for a contact far stiffer than the patch, and that a frame allocates nothing.
#include <gtest/gtest.h>

#include <vector>

#include "contact/local_model.hpp"
#include "core/counting_allocator.hpp"  // tests/core
#include "mesh/generators.hpp"

namespace tactus::contact {
namespace {

struct Plate {
  mesh::TriMesh mesh = mesh::grid_plate(0.1, 0.1, 10, 10);  // 10 mm cells in z = 0
  PatchCapacity capacity;
  PatchBuilder builder{mesh.vertices.size(), mesh.triangles, capacity};

  LocalPatch build(LocalModelKind kind, const Vec3& centre, double radius) {
    LocalPatch patch(kind, capacity);
    PatchBuilder::Inputs in;
    in.kind = kind;
    in.body = 0;
    in.center = centre;
    in.radius = radius;
    in.surface = mesh.vertices;
    in.material = {3e4, 0.45, 1000.0};
    in.frame_time = 1e-3;
    builder.build(in, patch);
    return patch;
  }
};

TEST(LocalPatch, TakesTheTrianglesTheSphereTouchesAndTheirNeighbours) {
  Plate plate;
  // A sphere of 6 mm around a point 1 mm off a vertex: its triangles' corners are free.
  const LocalPatch p = plate.build(LocalModelKind::mass_spring, Vec3(0.001, 0.001, 0.004), 0.006);
  ASSERT_TRUE(p.valid);
  EXPECT_GT(p.free_count, 0);
  EXPECT_LE(p.free_count, plate.capacity.free_nodes);
  EXPECT_GT(p.node_count, p.free_count);  // a border around the free nodes
  for (int n = 0; n < p.free_count; ++n)
    EXPECT_LT((p.position[static_cast<std::size_t>(n)] - Vec3(0.001, 0.001, 0.0)).norm(), 0.006 + 0.0142);
  // Every triangle with a free corner is in the patch, each once.
  for (int t = 0; t < p.triangle_count; ++t) {
    bool has_free = false;
    for (const mesh::Index v : p.triangles[static_cast<std::size_t>(t)]) has_free |= v < p.free_count;
    EXPECT_TRUE(has_free);
  }
  // Far from the plate: no patch.
  EXPECT_FALSE(plate.build(LocalModelKind::mass_spring, Vec3(0, 0, 0.05), 0.006).valid);
}

TEST(LocalPatch, MassSpringSettlesUnderAConstantForceAndReleasesWithout) {
  Plate plate;
  const LocalPatch p = plate.build(LocalModelKind::mass_spring, Vec3(0.0, 0.0, 0.004), 0.008);
  ASSERT_TRUE(p.valid);
  LocalModel model(LocalModelKind::mass_spring, plate.capacity);
  model.reset(p, 0.0);
  // A soft contact pressing the patch's first triangle at its centroid with a constant 0.5 N.
  PatchContact c;
  c.triangle = 0;
  c.barycentric = Vec3::Constant(1.0 / 3.0);
  c.normal = Vec3::UnitZ();
  c.force = 0.5;
  c.stiffness = 0.0;
  for (int k = 0; k < 2000; ++k) model.advance(c, 1e-3);
  const mesh::Triangle& tri = p.triangles[0];
  double dz = 0.0;
  for (const mesh::Index v : tri)
    if (v < p.free_count) dz += model.displacement()[3 * v + 2] / 3.0;
  // Pushed in, by about the force over the support stiffness of a node's share of the plate
  // (Boussinesq 2a·E/(1 − ν²) with a² = 1e-4/π): tens of newtons per metre per node.
  EXPECT_LT(dz, -1e-4);
  EXPECT_GT(dz, -0.05);
  // Released, it returns to the published shape.
  c.triangle = -1;
  for (int k = 0; k < 2000; ++k) model.advance(c, 1e-3);
  EXPECT_LT(model.displacement().head(3 * p.free_count).cwiseAbs().maxCoeff(), 1e-6);
}

TEST(LocalPatch, ImplicitContactIsStableForAContactMuchStifferThanThePatch) {
  Plate plate;
  const LocalPatch p = plate.build(LocalModelKind::mass_spring, Vec3(0.0, 0.0, 0.004), 0.008);
  ASSERT_TRUE(p.valid);
  LocalModel model(LocalModelKind::mass_spring, plate.capacity);
  model.reset(p, 0.0);
  // A penalty contact of 1e5 N/m held 1 mm into the patch's first triangle: the force the
  // model settles at must converge (no growing oscillation) and stay below k·depth.
  PatchContact c;
  c.triangle = 0;
  c.barycentric = Vec3::Constant(1.0 / 3.0);
  c.normal = Vec3::UnitZ();
  c.stiffness = 1e5;
  const double depth0 = 1e-3;
  double force = 0.0, previous = 0.0, last_change = 0.0;
  for (int k = 0; k < 500; ++k) {
    double s = 0.0;
    for (const mesh::Index v : p.triangles[0])
      if (v < p.free_count) s += model.displacement()[3 * v + 2] / 3.0;
    c.force = std::max(0.0, c.stiffness * (depth0 + s));
    previous = force;
    force = model.advance(c, 1e-3);
    last_change = std::abs(force - previous);
  }
  EXPECT_GT(force, 0.0);
  EXPECT_LT(force, c.stiffness * depth0);
  EXPECT_LT(last_change, 1e-6 * c.stiffness * depth0);
}

TEST(LocalPatch, AFrameAllocatesNothing) {
  Plate plate;
  const LocalPatch a = plate.build(LocalModelKind::mass_spring, Vec3(0.0, 0.0, 0.004), 0.008);
  const LocalPatch b = plate.build(LocalModelKind::mass_spring, Vec3(0.01, 0.0, 0.004), 0.008);
  LocalModel model(LocalModelKind::mass_spring, plate.capacity);
  model.reset(a, 0.0);
  PatchContact c{0, Vec3::Constant(1.0 / 3.0), Vec3::UnitZ(), 0.3, 500.0};
  testing::AllocationCounter counter;
  for (int k = 0; k < 200; ++k) {
    if (k % 10 == 0) model.reset(k % 20 == 0 ? b : a, k * 1e-3);  // a new patch from the simulation
    model.extrapolate(k * 1e-3);
    (void)model.surface().closest_point(Vec3(0.0, 0.0, 0.005));
    model.advance(c, 1e-3);
  }
  EXPECT_EQ(counter.count(), 0u) << counter.bytes() << " bytes";
}

}  // namespace
}  // namespace tactus::contact
