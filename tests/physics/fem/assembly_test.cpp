// The direct solver's matrices: reassembled from the model's values at the places the first
// assembly's triplets landed, and factorized with an order found on the nodes' graph.
#include <gtest/gtest.h>

#include <Eigen/CholmodSupport>
#include <memory>
#include <vector>

#include "fem_test_util.hpp"
#include "../triplets_only.hpp"
#include "physics/node_ordered_cholesky.hpp"

namespace tactus::physics {
namespace {

FemMaterial damped(FemLaw law) {
  FemMaterial m = fem_test::material(law, 2e4, 0.4);
  m.rayleigh_mass = 0.5;
  m.rayleigh_stiffness = 0.01;
  return m;
}

TEST(FemAssembly, MatrixValuesComeInTheTripletsOrder) {
  const mesh::TetMesh mesh = mesh::box_volume(Vec3(0.02, 0.01, 0.01), 2, 1, 1);
  for (FemLaw law : fem_test::all_laws())
    for (FemMass mass : {FemMass::lumped, FemMass::consistent}) {
      const TetFem fem(mesh, damped(law), mass);
      const auto s = fem.make_scratch();
      const VecX x = fem_test::deformed(fem.rest_positions(), fem_test::rotation(0.2, Vec3(1, 1, 0)) *
                                                                  Vec3(1.1, 0.95, 1.0).asDiagonal());
      const VecX v = VecX::Zero(x.size()), q = VecX::Zero(static_cast<Eigen::Index>(fem.internal_size()));
      fem.linearize(x, v, q, *s);
      std::vector<Triplet> triplets;
      fem.add_triplets(0.7, 0.3, triplets, *s);
      fem.add_mass_triplets(2.5, triplets);
      std::vector<std::int32_t> slots(triplets.size());
      for (std::size_t k = 0; k < slots.size(); ++k) slots[k] = static_cast<std::int32_t>(k);
      slots[3] = -1;  // a dropped entry gets nothing
      std::vector<double> values(triplets.size(), 0.0);
      ASSERT_TRUE(fem.add_matrix_values(0.7, 0.3, 2.5, slots, values.data(), *s)) << to_string(law);
      for (std::size_t k = 0; k < triplets.size(); ++k)
        ASSERT_EQ(values[k], k == 3 ? 0.0 : triplets[k].value()) << to_string(law) << " triplet " << k;

      // Slots for another set of triplets (without the mass): refused, nothing written.
      std::vector<double> untouched(triplets.size(), 0.0);
      EXPECT_FALSE(fem.add_matrix_values(0.7, 0.3, 0.0, slots, untouched.data(), *s));
      EXPECT_EQ(untouched, std::vector<double>(triplets.size(), 0.0));
    }
}

/// Positions after implicit Cholesky steps, then a static push, with the model as given.
VecX stepped_and_pushed(std::shared_ptr<const ForceModel> model) {
  Body b;
  b.model = std::move(model);
  b.settings.solver = LinearSolver::cholesky;
  b.settings.newton_iterations = 3;
  b.settings.newton_tolerance = 1e-12;
  // Held at x = 0, pulled down at x = 2 cm.
  const VecX& rest = b.model->rest_positions();
  b.fixed_dofs.assign(static_cast<std::size_t>(rest.size()), 0);
  VecX f = VecX::Zero(rest.size());
  for (Eigen::Index i = 0; i < rest.size(); i += 3) {
    if (rest[i] < 1e-9)
      for (int k = 0; k < 3; ++k) b.fixed_dofs[static_cast<std::size_t>(i + k)] = 1;
    if (rest[i] > 0.02 - 1e-9) f[i + 2] = -0.02;
  }
  b.gravity = Vec3(0, 0, -9.81);
  BodyState s = make_state(b);
  for (int i = 0; i < 10; ++i) step(b, s, 2e-3);
  // The static pull in two load steps, from the state the steps left.
  for (int k = 1; k <= 2; ++k) {
    const VecX load = (0.5 * k) * f;
    EXPECT_TRUE(solve_static(b, s, load).converged);
  }
  return s.x;
}

TEST(FemAssembly, ValuesAssembleTheSameBitsAsTriplets) {
  // The solver reassembles TetFem's matrices from values after the first assembly; a model
  // without them assembles from triplets every time. Same additions in the same order: the
  // same bits, for implicit steps (mass, Rayleigh damping, held nodes) and static solves.
  const mesh::TetMesh mesh = mesh::box_volume(Vec3(0.02, 0.01, 0.01), 4, 2, 2);
  for (FemLaw law : {FemLaw::corotational, FemLaw::neo_hookean})
    for (FemMass mass : {FemMass::lumped, FemMass::consistent}) {
      const auto fem = std::make_shared<TetFem>(mesh, damped(law), mass);
      const VecX from_values = stepped_and_pushed(fem);
      const VecX from_triplets = stepped_and_pushed(std::make_shared<testing::TripletsOnly>(fem));
      ASSERT_TRUE(from_values.allFinite());
      EXPECT_EQ(from_values, from_triplets) << to_string(law) << (mass == FemMass::consistent ? ", consistent" : "");
      EXPECT_GT((from_values - fem->rest_positions()).cwiseAbs().maxCoeff(), 1e-4) << "the body barely moved";
    }
}

TEST(NodeOrderedCholesky, SolvesAsCholmodsOwnOrderWithAboutItsFill) {
  // A 3-dof-per-node stiffness (held face on the identity) ordered on the nodes' graph:
  // the same solution to round-off (the matrix's condition number is about 1e4, so 1e-10
  // relative leaves room) and a factor within a tenth of CHOLMOD's own fill.
  const mesh::TetMesh mesh = mesh::box_volume(Vec3(0.04, 0.02, 0.02), 8, 4, 4);
  const TetFem fem(mesh, fem_test::material(FemLaw::linear, 1e4, 0.3));
  const auto s = fem.make_scratch();
  const VecX x = fem.rest_positions(), zero = VecX::Zero(x.size());
  fem.linearize(x, zero, VecX(), *s);
  std::vector<Triplet> all, lower;
  fem.add_triplets(1.0, 0.0, all, *s);
  std::vector<char> held(static_cast<std::size_t>(x.size()), 0);
  for (std::int32_t n : fem_test::nodes_at(mesh, 0, 0.0))
    for (int k = 0; k < 3; ++k) held[3 * static_cast<std::size_t>(n) + k] = 1;
  for (const Triplet& t : all)
    if (t.row() >= t.col() && !held[static_cast<std::size_t>(t.row())] && !held[static_cast<std::size_t>(t.col())])
      lower.push_back(t);
  for (Eigen::Index i = 0; i < x.size(); ++i) lower.emplace_back(i, i, held[static_cast<std::size_t>(i)] ? 1.0 : 0.0);
  SparseMatrix a(x.size(), x.size());
  a.setFromTriplets(lower.begin(), lower.end());
  const VecX rhs = VecX::LinSpaced(x.size(), -1.0, 1.0);

  Eigen::CholmodSupernodalLLT<SparseMatrix> own(a);
  NodeOrderedCholesky by_nodes;
  by_nodes.analyze_by_nodes(a);
  by_nodes.factorize(a);
  ASSERT_EQ(own.info(), Eigen::Success);
  ASSERT_EQ(by_nodes.info(), Eigen::Success);
  const VecX expected = own.solve(rhs), got = by_nodes.solve(rhs);
  EXPECT_LT((got - expected).norm(), 1e-10 * expected.norm());
  EXPECT_LT(by_nodes.cholmod().lnz, 1.1 * own.cholmod().lnz);
  EXPECT_EQ(by_nodes.cholmod().method[0].ordering, own.cholmod().method[0].ordering) << "the settings are restored";

  // Not a multiple of three: CHOLMOD's own analysis.
  SparseMatrix odd(4, 4);
  odd.setIdentity();
  NodeOrderedCholesky fallback;
  fallback.analyze_by_nodes(odd);
  fallback.factorize(odd);
  ASSERT_EQ(fallback.info(), Eigen::Success);
  EXPECT_EQ(fallback.solve(VecX::Ones(4)), VecX::Ones(4));
}

}  // namespace
}  // namespace tactus::physics
