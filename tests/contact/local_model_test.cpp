// The local patch on its own: which nodes and triangles it takes, that the mass-spring patch
// settles where its springs balance the contact, that the implicit contact solve is stable
// for a contact far stiffer than the patch, and that a frame allocates nothing.
#include <gtest/gtest.h>

#include <array>
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

  LocalPatch build(LocalModelKind kind, const Vec3& centre, double radius, bool rigid = false) {
    LocalPatch patch(kind, capacity);
    PatchBuilder::Inputs in;
    in.rigid = rigid;
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

TEST(LocalPatch, ARigidBodysPatchDoesNotYieldUnderEitherModel) {
  Plate plate;
  for (const LocalModelKind kind : {LocalModelKind::mass_spring, LocalModelKind::compliance}) {
    const LocalPatch p = plate.build(kind, Vec3(0.0, 0.0, 0.004), 0.008, /*rigid=*/true);
    ASSERT_TRUE(p.valid);
    LocalModel model(kind, plate.capacity);
    model.reset(p, 0.0);
    const PatchContact c{0, Vec3::Constant(1.0 / 3.0), Vec3::UnitZ(), 5.0, 0.0};  // 5 N at the centroid
    for (int k = 0; k < 100; ++k) model.advance(c, 1e-3);
    EXPECT_EQ(model.displacement().head(3 * p.free_count).norm(), 0.0) << local_model_name(kind);
  }
}

TEST(LocalPatch, AModelTakesOnlyPatchesOfItsCapacityAndKind) {
  Plate plate;
  const LocalPatch p = plate.build(LocalModelKind::mass_spring, Vec3(0.0, 0.0, 0.004), 0.008);
  ASSERT_TRUE(p.valid);
  LocalModel same(LocalModelKind::mass_spring, plate.capacity);
  EXPECT_NO_THROW(same.reset(p, 0.0));
  EXPECT_EQ(&same.patch(), &p);  // referred to in place, not copied
  PatchCapacity smaller = plate.capacity;
  smaller.free_nodes = 8;
  LocalModel other(LocalModelKind::mass_spring, smaller);
  EXPECT_THROW(other.reset(p, 0.0), std::invalid_argument);
  LocalModel compliance(LocalModelKind::compliance, plate.capacity);
  EXPECT_THROW(compliance.reset(p, 0.0), std::invalid_argument);
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

/// The patch triangle under (x, y) and the point's barycentric coordinates there.
PatchContact contact_at(const LocalModel& model, double x, double y, double force, double stiffness) {
  const ClosestSurfacePoint p = model.surface().closest_point(Vec3(x, y, 0.001));
  EXPECT_TRUE(p.found);
  return {p.triangle, p.barycentric, Vec3::UnitZ(), force, stiffness, -1.0};  // on the triangle's corners
}

/// How far the patch moved along z at (x, y) (the free corners' share of it).
double dent_at(const LocalModel& model, const PatchContact& c) {
  double dz = 0.0;
  for (int k = 0; k < 3; ++k) {
    const int v = model.patch().triangles[static_cast<std::size_t>(c.triangle)][static_cast<std::size_t>(k)];
    if (v < model.patch().free_count) dz += c.barycentric[k] * model.displacement()[3 * v + 2];
  }
  return dz;
}

TEST(LocalPatch, EverySphereOfASphereSetDentsThePatchUnderItsOwnForce) {
  // Two fingertip spheres 12 mm apart on a patch around both (a sphere-set finger): each
  // contact dents the patch where it is, under its own force.
  Plate plate;
  for (const LocalModelKind kind : {LocalModelKind::mass_spring, LocalModelKind::compliance}) {
    const LocalPatch p = plate.build(kind, Vec3(0.0, 0.0, 0.004), 0.016);
    ASSERT_TRUE(p.valid);
    LocalModel both(kind, plate.capacity), left(kind, plate.capacity), right(kind, plate.capacity);
    both.reset(p, 0.0), left.reset(p, 0.0), right.reset(p, 0.0);
    // Prescribed forces (slope 0): the linear patch superposes the two dents exactly.
    const std::array<PatchContact, 2> pair{contact_at(both, -0.006, 0.001, 0.4, 0.0),
                                           contact_at(both, 0.006, -0.001, 0.2, 0.0)};
    ASSERT_NE(pair[0].triangle, pair[1].triangle);
    std::array<double, 2> settled{};
    for (int k = 0; k < 300; ++k) {
      both.advance(pair, 1e-3, settled);
      left.advance(pair[0], 1e-3);
      right.advance(pair[1], 1e-3);
    }
    EXPECT_DOUBLE_EQ(settled[0], 0.4);
    EXPECT_DOUBLE_EQ(settled[1], 0.2);
    const VecX sum = left.displacement() + right.displacement();
    EXPECT_LT((both.displacement() - sum).cwiseAbs().maxCoeff(), 1e-9 * sum.cwiseAbs().maxCoeff() + 1e-15);
    if (kind == LocalModelKind::compliance) continue;  // a patch without a body is rigid: no dent
    EXPECT_LT(dent_at(both, pair[0]), 0.0);
    EXPECT_LT(dent_at(both, pair[1]), 0.0);
    EXPECT_LT(dent_at(both, pair[0]), dent_at(both, pair[1]));  // the harder press dents deeper
  }
}

TEST(LocalPatch, SphereSetForcesAreSolvedTogetherAndNeverPull) {
  Plate plate;
  const LocalPatch p = plate.build(LocalModelKind::mass_spring, Vec3(0.0, 0.0, 0.004), 0.016);
  ASSERT_TRUE(p.valid);
  // One contact through the span form is the single-contact solve, to the last bit.
  LocalModel one(LocalModelKind::mass_spring, plate.capacity), span(LocalModelKind::mass_spring, plate.capacity);
  one.reset(p, 0.0), span.reset(p, 0.0);
  const PatchContact c = contact_at(one, -0.006, 0.001, 0.5, 2000.0);
  for (int k = 0; k < 50; ++k) {
    double settled = 0.0;
    const double f = one.advance(c, 1e-3);
    span.advance(std::span<const PatchContact>(&c, 1), 1e-3, std::span<double>(&settled, 1));
    ASSERT_EQ(f, settled);
  }
  EXPECT_EQ(one.displacement(), span.displacement());

  // Two stiff contacts (1e4 N/m) held 1 mm deep, mirror images of each other: they settle at
  // the same force, and each below what it settles at alone, since the other's dent lowers
  // its point too; a third contact lifted off the surface (its law says −1 N) pushes nothing.
  LocalModel pair(LocalModelKind::mass_spring, plate.capacity), single(LocalModelKind::mass_spring, plate.capacity);
  pair.reset(p, 0.0), single.reset(p, 0.0);
  std::array<PatchContact, 3> contacts{contact_at(pair, -0.005, -0.002, 0.0, 1e4), contact_at(pair, 0.005, 0.002, 0.0, 1e4),
                                       contact_at(pair, 0.0, 0.009, -1.0, 1e4)};
  std::array<double, 3> settled{};
  double alone = 0.0;
  for (int k = 0; k < 3000; ++k) {
    for (int i = 0; i < 2; ++i) contacts[static_cast<std::size_t>(i)].force = 1e4 * (1e-3 + dent_at(pair, contacts[static_cast<std::size_t>(i)]));
    pair.advance(contacts, 1e-3, settled);
    PatchContact lone = contacts[0];
    lone.force = 1e4 * (1e-3 + dent_at(single, lone));
    alone = single.advance(lone, 1e-3);
  }
  EXPECT_GT(settled[0], 0.0);
  EXPECT_NEAR(settled[0], settled[1], 0.02 * settled[0]) << settled[0] << " vs " << settled[1] << " alone " << alone;
  EXPECT_LT(settled[0], alone);
  EXPECT_LT(alone, 10.0);  // below k·depth: the patch yields
  EXPECT_EQ(settled[2], 0.0);
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
    // A sphere-set finger: several contacts at once.
    const std::array<PatchContact, 3> set{c, c, PatchContact{}};
    std::array<double, 3> settled{};
    model.advance(set, 1e-3, settled);
  }
  EXPECT_EQ(counter.count(), 0u) << counter.bytes() << " bytes";
}

}  // namespace
}  // namespace tactus::contact
