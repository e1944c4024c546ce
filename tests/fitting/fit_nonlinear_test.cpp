// Recovering known parameters of the nonlinear laws under a sphere (the active set's
// passes make these the slow ones: `scenario`, release build only) (fit_test_util.hpp): each known parameter must lie within 3
// reported standard deviations of its estimate and within a few percent of it. Coarse
// meshes: the forward model is the same in the synthesis and the fit, so the mesh's own
// error does not enter.
#include <gtest/gtest.h>

#include "fit_test_util.hpp"

namespace tactus::fitting {
namespace {

using namespace test;

TEST(FitRecovers, CorotationalYoungModulusUnderASphere) {
  Experiment e = block(IndenterShape::sphere, 0.008, FemLaw::corotational, 0.012, {8, 8, 3});
  add(e, "young_modulus", std::nullopt, true);
  add(e, "poisson_ratio", 0.4, false);
  e.x = steps(2e-3, 12);
  const std::vector<double> truth{5e3, 0.4};
  const FitResult r = recover(e, truth);
  expect_recovered(e, r, truth, 5.0);
}


TEST(FitRecovers, TissueYoungModulusUnderASoftFinger) {
  // A finger as soft as the tissue takes half the approach: the fit must see through it.
  Experiment e = block(IndenterShape::finger, 0.008, FemLaw::corotational, 0.012, {8, 8, 3});
  e.indenter.finger.youngs_modulus = 1e4;
  add(e, "young_modulus", std::nullopt, true);
  add(e, "poisson_ratio", 0.4, false);
  e.x = steps(2e-3, 12);
  const std::vector<double> truth{5e3, 0.4};
  const FitResult r = recover(e, truth);
  expect_recovered(e, r, truth, 5.0);
}

TEST(FitRecovers, TissueYoungModulusUnderAFingerpad) {
  Experiment e = block(IndenterShape::fingerpad, 0.008, FemLaw::corotational, 0.012, {8, 8, 3});
  add(e, "young_modulus", std::nullopt, true);
  add(e, "poisson_ratio", 0.4, false);
  e.x = steps(3e-3, 12);
  const std::vector<double> truth{5e3, 0.4};
  const FitResult r = recover(e, truth);
  expect_recovered(e, r, truth, 5.0);
}

TEST(FitRecovers, CorotationalYoungModulusAndPoissonRatioOfAThinLayer) {
  // A punch on a thin bonded layer at 15 % compression: ν sets how hard the layer resists
  // (Hayes et al. 1972), the corotational law's geometric stiffening separates it from E.
  // The two trade off, so ν's reported uncertainty is wide; the truth must still lie within it.
  Experiment e = block(IndenterShape::flat_punch, 0.008, FemLaw::corotational, 0.004, {8, 8, 2});
  add(e, "young_modulus", 4e3, true);
  add(e, "poisson_ratio", 0.3, true);
  e.x = steps(0.6e-3, 12);
  const std::vector<double> truth{6e3, 0.42};
  const FitResult r = recover(e, truth);
  EXPECT_TRUE(r.converged) << r.status;
  for (std::size_t i = 0; i < 2; ++i)
    EXPECT_LE(std::abs(r.values[i] - truth[i]), 3.0 * r.sigma[i]) << r.names[i] << " " << r.values[i];
}


TEST(FitRecovers, NeoHookeanShearModulus) {
  Experiment e = block(IndenterShape::sphere, 0.008, FemLaw::neo_hookean, 0.012, {8, 8, 3});
  add(e, "mu", std::nullopt, true);
  add(e, "kappa", 5e4, false);
  e.x = steps(2.5e-3, 12);
  const std::vector<double> truth{2e3, 5e4};
  const FitResult r = recover(e, truth);
  expect_recovered(e, r, truth, 5.0);
}


}  // namespace
}  // namespace tactus::fitting
