// docs/fitting.md's example, as printed there: examples/fitting/sphere.toml fitted from its
// analytic first guess (Hertz with the layer's stiffening). A change that moves the guess,
// the fit or the optimizer's path moves these numbers and must change the docs with them.
#include <gtest/gtest.h>

#include <filesystem>

#include "fitting/experiment.hpp"
#include "fitting/fit.hpp"
#include "fitting/indentation.hpp"

namespace tactus::fitting {
namespace {

TEST(FittingExample, SphereFitAsDocumented) {
  const Experiment e = read_experiment(std::filesystem::path(TACTUS_SOURCE_DIR) / "examples/fitting/sphere.toml");
  const IndentationModel model(e);
  const FitResult r = fit(e, model);
  ASSERT_EQ(r.names.front(), "young_modulus");
  EXPECT_NEAR(r.initial.front(), 4478.27, 0.01);
  EXPECT_NE(r.guess_method.find("Dimitriadis"), std::string::npos) << r.guess_method;
  EXPECT_NEAR(r.values.front(), 3574.56, 0.01);
  EXPECT_NEAR(r.sigma.front(), 29.8, 0.05);
  EXPECT_EQ(r.iterations, 5);
}

}  // namespace
}  // namespace tactus::fitting
