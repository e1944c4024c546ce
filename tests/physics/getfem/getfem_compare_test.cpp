// Static StVK, neo-Hookean and Mooney-Rivlin solutions against GetFEM, an independent FEM
// library: the same P1 mesh, energy density, loads and fixed dofs go to
// getfem_reference.py, whose nodal displacements must match Tactus's to 1e-6 relative.
#include <gtest/gtest.h>

#include "getfem_harness.hpp"

namespace tactus::physics::getfem {
namespace {

/// Solves the case in both codes and compares the nodal displacements.
void compare(const Case& c) {
  if (!getfem_available())
    GTEST_SKIP() << "GetFEM is not installed for " << python()
                 << " (Debian: apt-get install python3-getfem; scripts/setup installs it)";
  const auto t0 = std::chrono::steady_clock::now();
  const Solution t = solve_tactus(c);
  const auto t1 = std::chrono::steady_clock::now();
  ASSERT_TRUE(t.result.converged) << c.name << ": residual " << t.result.residual
                                  << (t.result.inverted ? " (inverted)" : "");
  // Below the inversion threshold Tactus continues the volumetric terms by a Taylor
  // expansion; above it both codes minimize the same energy.
  ASSERT_GT(t.min_J, c.material.inversion_threshold) << c.name;

  const fs::path dir = fs::temp_directory_path() / ("tactus_getfem_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const GetFemSolution gs = solve_getfem(c, dir);
  const auto t2 = std::chrono::steady_clock::now();
  fs::remove_all(dir);
  ASSERT_TRUE(gs.error.empty()) << gs.error;
  const VecX& g = gs.u;
  ASSERT_EQ(g.size(), t.u.size());

  double max_u = 0.0, max_diff = 0.0;
  for (Eigen::Index i = 0; i < g.size(); i += 3) {
    max_u = std::max(max_u, g.segment<3>(i).norm());
    max_diff = std::max(max_diff, (t.u.segment<3>(i) - g.segment<3>(i)).norm());
  }
  const double rel = max_diff / max_u;
  using ms = std::chrono::duration<double, std::milli>;
  std::printf("%-20s %4zu tets  max|u| %.4e m  min J %.3f  Newton residual %.1e  max rel diff %.2e  "
              "(Tactus %.0f ms, GetFEM %.0f ms)\n",
              c.name.c_str(), c.mesh.tets.size(), max_u, t.min_J, t.result.residual, rel, ms(t1 - t0).count(),
              ms(t2 - t1).count());
  EXPECT_LT(rel, 1e-6) << c.name;
}

TEST(GetFemComparison, BlockStvk) { compare(block(FemLaw::stvk)); }
TEST(GetFemComparison, BlockNeoHookean) { compare(block(FemLaw::neo_hookean)); }
TEST(GetFemComparison, BlockMooneyRivlin) { compare(block(FemLaw::mooney_rivlin)); }
TEST(GetFemComparison, BeamStvk) { compare(beam(FemLaw::stvk)); }
TEST(GetFemComparison, BeamNeoHookean) { compare(beam(FemLaw::neo_hookean)); }
TEST(GetFemComparison, BeamMooneyRivlin) { compare(beam(FemLaw::mooney_rivlin)); }
TEST(GetFemComparison, SqueezedNeoHookean60PercentInOneStep) { compare(squeezed_block(FemLaw::neo_hookean, 0.6, 1)); }
TEST(GetFemComparison, SqueezedMooneyRivlin60PercentInOneStep) {
  compare(squeezed_block(FemLaw::mooney_rivlin, 0.6, 1));
}
/// Mooney–Rivlin at ν = 0.49 with the pressure at the nodes (volumetric = "nodal"), against
/// GetFEM's mixed P1–P1 displacement–pressure formulation with the pressure's mass lumped
/// (getfem_reference.py, mooney_rivlin_nodal): one discrete problem, condensed in Tactus.
Case nodal(Case c) {
  c.name += "_nodal";
  c.material.poisson_ratio = 0.49;
  c.material.bulk_modulus.reset();  // κ from E and ν: 50 times the shear modulus
  c.material.young_modulus = 2.0 * 2.0 * (*c.material.c10 + *c.material.c01) * (1.0 + 0.49);
  c.material.nodal_pressure = true;
  return c;
}
TEST(GetFemComparison, BlockMooneyRivlinNodalPressure) { compare(nodal(block(FemLaw::mooney_rivlin))); }
TEST(GetFemComparison, SqueezedMooneyRivlinNodalPressure30PercentIn3Steps) {
  compare(nodal(squeezed_block(FemLaw::mooney_rivlin, 0.3, 3)));
}
TEST(GetFemComparison, LiverMooneyRivlinNodalPressurePushed2cmIn4Steps) {
  Case c = liver(FemLaw::mooney_rivlin, 0.02, 4);
  c.material.c10 = 700.0;
  c.material.c01 = 300.0;
  compare(nodal(c));
}
TEST(GetFemComparison, LiverStvkPushed1cmInOneStep) { compare(liver(FemLaw::stvk, 0.01, 1)); }
TEST(GetFemComparison, LiverStvkPushed1cmIn4Steps) { compare(liver(FemLaw::stvk, 0.01, 4)); }
TEST(GetFemComparison, LiverNeoHookeanPushed2cmIn4Steps) { compare(liver(FemLaw::neo_hookean, 0.02, 4)); }
TEST(GetFemComparison, LiverNeoHookeanPushed3cmIn12Steps) { compare(liver(FemLaw::neo_hookean, 0.03, 12)); }

/// Past about 2 cm the StVK liver's own equilibrium path turns an element inside out (StVK's
/// energy stays finite through J = 0; GetFEM follows the path there): Tactus must refuse
/// that state rather than report it converged.
TEST(GetFemComparison, LiverStvkPushedPastItsInversionIsRefused) {
  if (!getfem_available()) GTEST_SKIP() << "GetFEM is not installed for " << python();
  const Case c = liver(FemLaw::stvk, 0.0225, 9);
  const Solution t = solve_tactus(c);
  EXPECT_FALSE(t.result.converged);
  EXPECT_TRUE(t.result.inverted);

  const fs::path dir = fs::temp_directory_path() / ("tactus_getfem_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const GetFemSolution gs = solve_getfem(c, dir);
  fs::remove_all(dir);
  ASSERT_TRUE(gs.error.empty()) << gs.error;
  const VecX& g = gs.u;
  ASSERT_EQ(g.size(), t.u.size());
  const auto fem = std::make_shared<TetFem>(c.mesh, c.material);
  const VecX x = fem->rest_positions() + g;
  double min_J = 1e300;
  for (std::size_t e = 0; e < fem->elements().size(); ++e)
    min_J = std::min(min_J, fem->deformation_gradient(x, e).determinant());
  EXPECT_LT(min_J, 0.0) << "GetFEM's equilibrium is right side out: the refusal would be wrong";
}

}  // namespace
}  // namespace tactus::physics::getfem
