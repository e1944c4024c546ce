// The cloth model's derivatives against finite differences of its own energy and forces,
// its conservation of momentum, the agreement of its linear-algebra views, the curvature of
// a sheet rolled onto a cylinder, and bad meshes refused.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/SparseCore>
#include <cmath>
#include <numbers>
#include <random>

#include "../triplets_only.hpp"
#include "core/error.hpp"
#include "physics/body.hpp"
#include "physics/cloth/cloth_model.hpp"
#include "physics/cloth/sheet.hpp"

namespace tactus::physics {
namespace {

VecX random_vector(Eigen::Index n, unsigned seed, double scale) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-scale, scale);
  VecX v(n);
  for (auto& x : v) x = u(rng);
  return v;
}

/// Nonlinear curves in every term, and damping in every term.
ClothMaterial test_material() {
  ClothMaterial m;
  m.warp = MeasuredCurve({0.0, 0.02, 0.05, 0.1}, {0.0, 20.0, 120.0, 500.0}, MeasuredCurve::BelowZero::linear, 30.0, "warp");
  m.weft = MeasuredCurve({0.0, 0.03, 0.08}, {0.0, 10.0, 200.0}, MeasuredCurve::BelowZero::linear, 10.0, "weft");
  m.shear = MeasuredCurve({0.0, 0.1, 0.3}, {0.0, 5.0, 40.0}, MeasuredCurve::BelowZero::mirror, 0.0, "shear");
  m.bend_warp = MeasuredCurve({0.0, 10.0, 50.0}, {0.0, 1e-4, 1e-3}, MeasuredCurve::BelowZero::mirror, 0.0, "bend warp");
  m.bend_weft = MeasuredCurve::line(3e-5, "bend weft");
  m.areal_density = 0.15;
  m.stretch_damping = 0.002;
  m.shear_damping = 0.004;
  m.bend_damping = 0.01;
  return m;
}

struct Fixture {
  std::shared_ptr<ClothModel> model;
  VecX x, v;
};

Fixture make_fixture(SheetBending bending) {
  const auto sheet = rectangular_sheet(0.03, 0.02, 0.01, Vec3::Zero(), Vec3::UnitX(), Vec3::UnitY(), bending);
  Fixture f;
  f.model = std::make_shared<ClothModel>(sheet.cloth, test_material());
  const auto n = f.model->rest_positions().size();
  f.x = f.model->rest_positions() + random_vector(n, 1, 1.5e-3);  // ±15 % of the 10 mm cell
  f.v = random_vector(n, 2, 0.05);
  return f;
}

VecX forces(const ClothModel& m, const VecX& x, const VecX& v) {
  auto s = m.make_scratch();
  VecX f(x.size());
  m.forces(x, v, VecX(), f, *s);
  return f;
}

TEST(ClothModel, ForcesAreMinusTheEnergyGradient) {
  for (auto bending : {SheetBending::hinges, SheetBending::yarns}) {
  SCOPED_TRACE(bending == SheetBending::hinges ? "hinges" : "yarns");
  const Fixture f = make_fixture(bending);
  const VecX force = forces(*f.model, f.x, VecX::Zero(f.x.size()));
  const double h = 1e-7;
  for (Eigen::Index i = 0; i < f.x.size(); ++i) {
    VecX xp = f.x, xm = f.x;
    xp[i] += h;
    xm[i] -= h;
    const double derivative = (f.model->elastic_energy(xp, VecX()) - f.model->elastic_energy(xm, VecX())) / (2 * h);
    EXPECT_NEAR(force[i], -derivative, 1e-6 * (1.0 + force.cwiseAbs().maxCoeff())) << "dof " << i;
  }
  }
}

TEST(ClothModel, ShearFrictionForceIsMinusItsEnergyGradientAtFixedStickAngles) {
  // With the stick angles held, the friction is the gradient of a convex potential
  // (quadratic while it sticks, of slope ±H beyond): the force must be −∇E there, with some
  // triangles sticking and some slipping either way; with one width, and with a strength
  // that grows with the stick angle (2HG5 above 2HG), held with it.
  for (const double at_5 : {0.0, 5.0}) {
  SCOPED_TRACE(at_5);
  const auto sheet = rectangular_sheet(0.03, 0.02, 0.01);
  ClothMaterial m = test_material();
  m.shear_friction = 2.0;
  m.shear_friction_5 = at_5;
  m.shear_stick_angle = 0.01;
  const ClothModel model(sheet.cloth, m);
  ASSERT_EQ(model.internal_size(), model.triangles().size());
  const VecX x = model.rest_positions() + random_vector(model.rest_positions().size(), 1, 1.5e-3);
  VecX q(static_cast<Eigen::Index>(model.internal_size()));
  int sticking = 0, slipping = 0;
  for (std::size_t t = 0; t < model.triangles().size(); ++t) {
    const double gamma = model.triangle_strain(x, t)[2];
    const double offset = (t % 3 == 0 ? 0.5 : (t % 3 == 1 ? 3.0 : -3.0)) * m.shear_stick_angle;
    q[static_cast<Eigen::Index>(t)] = gamma - offset;
    (std::abs(offset) < m.shear_stick_angle ? sticking : slipping) += 1;
  }
  ASSERT_GT(sticking, 0);
  ASSERT_GT(slipping, 0);
  auto s = model.make_scratch();
  VecX force(x.size());
  model.forces(x, VecX::Zero(x.size()), q, force, *s);
  const double h = 1e-8;
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    VecX xp = x, xm = x;
    xp[i] += h;
    xm[i] -= h;
    const double derivative = (model.elastic_energy(xp, q) - model.elastic_energy(xm, q)) / (2 * h);
    EXPECT_NEAR(force[i], -derivative, 1e-6 * (1.0 + force.cwiseAbs().maxCoeff())) << "dof " << i;
  }
  // The step's end: the slipping triangles' stick angles follow, the sticking ones stay.
  VecX after = q;
  model.update_internal(x, 1e-3, after, *s);
  for (std::size_t t = 0; t < model.triangles().size(); ++t) {
    const auto i = static_cast<Eigen::Index>(t);
    const double slip = model.triangle_strain(x, t)[2] - after[i];
    if (t % 3 == 0)
      EXPECT_EQ(after[i], q[i]) << "triangle " << t;
    else
      EXPECT_NEAR(std::abs(slip), m.shear_stick_angle, 1e-15) << "triangle " << t;
  }
  }
}

TEST(ClothModel, ConservesLinearAndAngularMomentum) {
  for (auto bending : {SheetBending::hinges, SheetBending::yarns}) {
  SCOPED_TRACE(bending == SheetBending::hinges ? "hinges" : "yarns");
  const Fixture f = make_fixture(bending);
  const VecX force = forces(*f.model, f.x, f.v);  // with damping
  Vec3 sum = Vec3::Zero(), torque = Vec3::Zero();
  for (Eigen::Index n = 0; n < f.x.size() / 3; ++n) {
    sum += force.segment<3>(3 * n);
    torque += f.x.segment<3>(3 * n).cross(force.segment<3>(3 * n));
  }
  const double scale = force.norm();
  EXPECT_LT(sum.norm(), 1e-12 * scale);
  EXPECT_LT(torque.norm(), 1e-12 * scale);
  }
}

TEST(ClothModel, DampingForceIsMinusTheDampingMatrixTimesVelocity) {
  for (auto bending : {SheetBending::hinges, SheetBending::yarns}) {
  SCOPED_TRACE(bending == SheetBending::hinges ? "hinges" : "yarns");
  const Fixture f = make_fixture(bending);
  const VecX zero = VecX::Zero(f.x.size());
  auto s = f.model->make_scratch();
  f.model->linearize(f.x, f.v, VecX(), *s);
  VecX dv = VecX::Zero(f.x.size());
  f.model->add_damping_product(f.v, dv, *s);
  const VecX damping_force = forces(*f.model, f.x, f.v) - forces(*f.model, f.x, zero);
  EXPECT_GT(dv.norm(), 0.0);
  EXPECT_LT((damping_force + dv).norm(), 1e-10 * dv.norm());
  }
}

TEST(ClothModel, LinearizedForcesInOnePassAreTheThreeCallsBitForBit) {
  // The implicit step's f + K·dx: one pass over the elements must give what forces(),
  // linearize() and add_stiffness_product() give, to the last bit, and leave the same
  // linearization behind.
  for (auto bending : {SheetBending::hinges, SheetBending::yarns}) {
  SCOPED_TRACE(bending == SheetBending::hinges ? "hinges" : "yarns");
  const Fixture f = make_fixture(bending);
  const VecX dx = random_vector(f.x.size(), 7, 1e-3);
  auto one = f.model->make_scratch(), three = f.model->make_scratch();
  VecX combined(f.x.size()), separate(f.x.size());
  f.model->linearized_forces(f.x, f.v, VecX(), dx, combined, *one);
  f.model->forces(f.x, f.v, VecX(), separate, *three);
  f.model->linearize(f.x, f.v, VecX(), *three);
  f.model->add_stiffness_product(dx, separate, *three);
  EXPECT_TRUE((combined.array() == separate.array()).all());
  const VecX probe = random_vector(f.x.size(), 8, 1.0);
  VecX k1 = VecX::Zero(f.x.size()), k3 = VecX::Zero(f.x.size());
  f.model->add_system_product(1.0, 0.3, 0.7, probe, k1, *one);
  f.model->add_system_product(1.0, 0.3, 0.7, probe, k3, *three);
  EXPECT_TRUE((k1.array() == k3.array()).all());
  }
}

TEST(ClothModel, StiffnessIsExactWhereTheDroppedTermsVanish) {
  // Stretched in its plane without shear or bending: the shear and bending terms that the
  // Gauss–Newton tangent leaves out are proportional to the shear force and the moment, both
  // zero here, so K must equal the force's derivative exactly; with shear friction too (it
  // sticks at γ = 0 with the stick angles at 0, and its stiffness joins the shear's).
  for (auto bending : {SheetBending::hinges, SheetBending::yarns})
  for (double friction : {0.0, 2.0}) {
  SCOPED_TRACE(bending == SheetBending::hinges ? "hinges" : "yarns");
  SCOPED_TRACE(friction);
  Fixture f = make_fixture(bending);
  if (friction > 0.0) {
    ClothMaterial m = test_material();
    m.shear_friction = friction;
    m.shear_friction_5 = 2.0 * friction;
    m.shear_stick_angle = 0.01;
    f.model = std::make_shared<ClothModel>(
        rectangular_sheet(0.03, 0.02, 0.01, Vec3::Zero(), Vec3::UnitX(), Vec3::UnitY(), bending).cloth, m);
  }
  VecX x = f.model->rest_positions();
  for (Eigen::Index n = 0; n < x.size() / 3; ++n) {
    x[3 * n] *= 1.06;
    x[3 * n + 1] *= 1.04;
  }
  auto s = f.model->make_scratch();
  f.model->linearize(x, VecX::Zero(x.size()), VecX(), *s);
  for (unsigned seed = 10; seed < 13; ++seed) {
    const VecX dx = random_vector(x.size(), seed, 1.0);
    VecX kdx = VecX::Zero(x.size());
    f.model->add_stiffness_product(dx, kdx, *s);
    const double h = 1e-7;
    const VecX zero = VecX::Zero(x.size());
    const VecX fd = (forces(*f.model, x - h * dx, zero) - forces(*f.model, x + h * dx, zero)) / (2 * h);
    // 1e-5: the spline's second derivative jumps at its knots, which central differences see.
    EXPECT_LT((kdx - fd).norm(), 1e-5 * kdx.norm()) << "seed " << seed;
  }
  }
}

TEST(ClothModel, SheetsOfOneToTwoThousandNodesSweepTheirCgInTwoRanges) {
  // The stiff stretch costs CG tens of iterations a step, so the cloth splits its sweeps from
  // 1,024 nodes (the size rule: 2,048); below that, and from 2,048 on, the rule decides.
  for (const auto& [spacing, ranges] : {std::pair{0.01, 0u}, std::pair{0.005, 2u}, std::pair{0.004, 0u}}) {
    const ClothModel model(rectangular_sheet(0.2, 0.2, spacing).cloth, test_material());
    auto s = model.make_scratch();
    model.linearize(model.rest_positions(), VecX::Zero(model.rest_positions().size()), VecX(), *s);
    const BlockMatrix* A = model.assemble_system(1.0, 0.0, 1e-4, *s);
    ASSERT_NE(A, nullptr);
    EXPECT_EQ(A->sweep_ranges, ranges) << model.node_count() << " nodes";
  }
}

TEST(ClothModel, AssembledTripletDiagonalAndProductViewsAgreeAndArePositiveSemiDefinite) {
  for (auto bending : {SheetBending::hinges, SheetBending::yarns}) {
  SCOPED_TRACE(bending == SheetBending::hinges ? "hinges" : "yarns");
  const Fixture f = make_fixture(bending);
  auto s = f.model->make_scratch();
  f.model->linearize(f.x, f.v, VecX(), *s);
  const auto n = f.x.size();
  const double a = 3.0, b = 0.7, c = 1.3;
  // Dense matrices from the products.
  MatX K(n, n), D(n, n);
  for (Eigen::Index j = 0; j < n; ++j) {
    VecX e = VecX::Zero(n), k = VecX::Zero(n), d = VecX::Zero(n);
    e[j] = 1.0;
    f.model->add_stiffness_product(e, k, *s);
    f.model->add_damping_product(e, d, *s);
    K.col(j) = k;
    D.col(j) = d;
  }
  EXPECT_LT((K - K.transpose()).norm(), 1e-12 * K.norm());
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<MatX>(K).eigenvalues().minCoeff(), -1e-9 * K.norm());
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<MatX>(D).eigenvalues().minCoeff(), -1e-9 * D.norm());
  const MatX system = MatX(f.model->lumped_mass().asDiagonal()) * a + b * D + c * K;

  const BlockMatrix* A = f.model->assemble_system(a, b, c, *s);
  ASSERT_NE(A, nullptr);
  MatX assembled = MatX::Zero(n, n);
  for (std::size_t i = 0; i < A->diagonal.size(); ++i) {
    const auto r = 3 * static_cast<Eigen::Index>(i);
    assembled.block<3, 3>(r, r) = A->diagonal[i];
    for (auto k = A->row_start[i]; k < A->row_start[i + 1]; ++k) {
      const auto col = 3 * static_cast<Eigen::Index>(A->column[static_cast<std::size_t>(k)]);
      assembled.block<3, 3>(r, col) = A->upper[static_cast<std::size_t>(k)];
      assembled.block<3, 3>(col, r) = A->upper[static_cast<std::size_t>(k)].transpose();
    }
  }
  EXPECT_LT((assembled - system).norm(), 1e-12 * system.norm());

  std::vector<Triplet> triplets;
  f.model->add_triplets(c, b, triplets, *s);
  SparseMatrix sparse(n, n);
  sparse.setFromTriplets(triplets.begin(), triplets.end());
  EXPECT_LT((MatX(sparse) - (b * D + c * K)).norm(), 1e-12 * K.norm());

  VecX diagonal = VecX::Zero(n);
  f.model->add_diagonal(c, b, diagonal, *s);
  EXPECT_LT((diagonal - (b * D + c * K).diagonal()).norm(), 1e-12 * diagonal.norm());
  }
}

TEST(ClothModel, MatrixValuesComeInTheTripletsOrderAndStepTheSameBits) {
  for (auto bending : {SheetBending::hinges, SheetBending::yarns}) {
    SCOPED_TRACE(bending == SheetBending::hinges ? "hinges" : "yarns");
    const Fixture f = make_fixture(bending);
    auto s = f.model->make_scratch();
    f.model->linearize(f.x, f.v, VecX(), *s);
    std::vector<Triplet> triplets;
    f.model->add_triplets(0.3, 0.7, triplets, *s);
    f.model->add_mass_triplets(2.0, triplets);
    std::vector<std::int32_t> slots(triplets.size());
    for (std::size_t k = 0; k < slots.size(); ++k) slots[k] = static_cast<std::int32_t>(k);
    std::vector<double> values(triplets.size(), 0.0);
    ASSERT_TRUE(f.model->add_matrix_values(0.3, 0.7, 2.0, slots, values.data(), *s));
    for (std::size_t k = 0; k < triplets.size(); ++k) ASSERT_EQ(values[k], triplets[k].value()) << "triplet " << k;
    EXPECT_FALSE(f.model->add_matrix_values(0.3, 0.7, 0.0, slots, values.data(), *s));

    // Implicit steps by CHOLMOD, reassembled from values or from triplets: the same bits.
    auto run = [&](std::shared_ptr<const ForceModel> model) {
      Body body;
      body.model = std::move(model);
      body.settings.solver = LinearSolver::cholesky;
      body.gravity = Vec3(0.0, 0.0, -9.81);
      body.fix_nodes({0, 1});
      BodyState state = make_state(body);
      state.x = f.x;
      for (int k = 0; k < 8; ++k) step(body, state, 2e-3);
      return state.x;
    };
    const VecX from_values = run(f.model);
    EXPECT_EQ(from_values, run(std::make_shared<testing::TripletsOnly>(f.model)));
    EXPECT_GT((from_values - f.x).norm(), 1e-5);
  }
}

TEST(ClothModel, CurvatureOfASheetRolledOntoACylinderIsOneOverItsRadius) {
  // The seed's K = (2/σ)·cos(Θ/2), σ the mean height: exact for the circle through the two
  // opposite vertices and the edge. Rolled about the weft axis, the edges along the weft fold
  // by K = 1/R and no other edge folds; the bending energy is then ½·B·K² per unit area.
  const double radius = 0.05, width = 0.1, height = 0.04;
  ClothMaterial m = test_material();
  m.bend_warp = MeasuredCurve::line(2e-5, "warp bending");
  const auto sheet = rectangular_sheet(width, height, 0.0025, Vec3::Zero(), Vec3::UnitX(), Vec3::UnitY(),
                                      SheetBending::hinges);
  const ClothModel model(sheet.cloth, m);
  // Nodes on the circle one chord apart, so that no triangle stretches: the arc between two
  // columns is 2·asin(h/2R) and the curvature across each fold is exactly 1/R.
  const double step = 2.0 * std::asin(0.5 * 0.0025 / radius);
  VecX x = model.rest_positions();
  for (Eigen::Index n = 0; n < x.size() / 3; ++n) {
    const double phi = std::round(sheet.cloth.uv[static_cast<std::size_t>(n)].x() / 0.0025) * step;
    x[3 * n] = radius * std::sin(phi);
    x[3 * n + 2] = radius * (1.0 - std::cos(phi));
  }
  double bending = 0.0;
  for (std::size_t h = 0; h < model.hinges().size(); ++h) {
    const auto& hinge = model.hinges()[h];
    const double k = std::abs(model.hinge_curvature(x, h));
    if (hinge.warp_share == 1.0)
      EXPECT_NEAR(k, 1.0 / radius, 1e-9 / radius) << "hinge " << h;
    else
      EXPECT_LT(k, 1e-9 / radius) << "hinge " << h;
    bending += hinge.area * 0.5 * 2e-5 * k * k;
  }
  // Stretch and shear are zero on the isometric roll: the whole energy is bending. The hinges
  // along the weft cover the sheet less its first and last column of cells.
  const double cells = std::round(width / 0.0025);
  const double expected = 0.5 * 2e-5 / (radius * radius) * width * height * (cells - 1) / cells;
  EXPECT_NEAR(bending, expected, 1e-9 * expected);
  EXPECT_NEAR(model.elastic_energy(x, VecX()), bending, 1e-9 * bending);

  // Along the yarns: the warp lines curve by exactly 1/R, the weft lines stay straight, and the
  // energy is ½·B·K² over the area the bends stand for (all but half a column at each end).
  const auto yarn_sheet = rectangular_sheet(width, height, 0.0025);
  const ClothModel yarn_model(yarn_sheet.cloth, m);
  for (std::size_t y = 0; y < yarn_model.yarns().size(); ++y)
    EXPECT_NEAR(yarn_model.yarn_curvature(x, y), yarn_model.yarns()[y].warp ? 1.0 / radius : 0.0, 1e-9 / radius);
  const double yarn_expected = 0.5 * 2e-5 / (radius * radius) * width * height * (cells - 1) / cells;
  EXPECT_NEAR(yarn_model.elastic_energy(x, VecX()), yarn_expected, 1e-9 * yarn_expected);
}

TEST(ClothModel, RefusesBadMeshesAndMaterials) {
  auto sheet = rectangular_sheet(0.02, 0.02, 0.01);
  ClothMaterial m = test_material();
  auto bad = sheet.cloth;
  // A third triangle on the edge (0, 4): non-manifold.
  bad.mesh.vertices.push_back(Vec3(0.0, 0.0, 0.01));
  bad.uv.push_back(Vec2(0.0, -0.01));
  bad.mesh.triangles.push_back({0, 4, 9});
  EXPECT_THROW(ClothModel(bad, m), InputError);
  auto degenerate = sheet.cloth;
  degenerate.uv[4] = degenerate.uv[0];
  try {
    ClothModel model(degenerate, m);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("has no area in (u, v)"), std::string::npos) << e.what();
  }
  auto short_uv = sheet.cloth;
  short_uv.uv.pop_back();
  EXPECT_THROW(ClothModel(short_uv, m), InputError);
  m.areal_density = -1.0;
  EXPECT_THROW(ClothModel(sheet.cloth, m), InputError);
}

}  // namespace
}  // namespace tactus::physics
