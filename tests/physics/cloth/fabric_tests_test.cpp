// The textile tests a fabric laboratory runs, on the simulated fabric, against references
// the model does not contain:
// - hang test (seed 002 §VI, Fig. 8): elongation of a hanging strip under a bottom load
//   against the integral of the tensile curve along the strip;
// - Peirce's cantilever (the bending-length standard): the large-deflection elastica of a
//   heavy strip, and the bending length c = (B/W)^(1/3) read the standard's way;
// - picture frame: the frame's force against the shear curve;
// - energy: a released undamped fabric does not gain energy.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "physics/body.hpp"
#include "physics/cloth/kes.hpp"
#include "physics/cloth/sheet.hpp"
#include "fabric_lab.hpp"

namespace tactus::physics {
namespace {

using namespace fabric_lab;

TEST(FabricHangTest, ElongationMatchesTheTensileCurveWithin1PercentAndConvergesUnderRefinement) {
  const ClothMaterial m = kes_material(test_fabric(), "test fabric");
  const double width = 0.20, length = 0.38;
  double previous_worst = std::numeric_limits<double>::infinity();
  for (double spacing : {0.02, 0.01, 0.005}) {
    Hang h = hanging_strip(m, width, length, spacing);
    double worst = 0.0;
    for (double load : {0.4, 0.8, 1.2, 1.6, 2.0, 2.4}) {
      bool converged = false;
      const double simulated = simulated_elongation(h, load, length, converged);
      EXPECT_TRUE(converged) << "load " << load;
      const double analytic = analytic_elongation(m, load, width, length);
      const double error = std::abs(simulated - analytic) / analytic;
      worst = std::max(worst, error);
      RecordProperty("spacing_" + std::to_string(spacing) + "_load_" + std::to_string(load), std::to_string(error));
      if (spacing <= 0.01) {
        EXPECT_LT(error, 0.01) << "spacing " << spacing << " load " << load;
      }
    }
    EXPECT_LT(worst, previous_worst) << "no convergence at spacing " << spacing;
    previous_worst = worst;
  }
}

TEST(FabricCantilever, PeirceBendingLengthWithin5PercentAndTheElasticaWithinOneDegree) {
  const ClothMaterial m = kes_material(test_fabric(), "test fabric");
  const double bending = m.bend_warp.slope(0.0), weight = m.areal_density * kGravity;
  const double c = std::cbrt(bending / weight);
  // The reference: Peirce's 41.5° holds for the elastica at l = 2c (his fit, within 0.5°).
  const double deg = 180.0 / std::numbers::pi;
  EXPECT_NEAR(elastica_chord_angle(2.0) * deg, 41.5, 0.5);
  const double spacing = c / 8.0;
  for (double ratio : {1.5, 2.0, 2.5}) {
    bool converged = false;
    const double simulated = simulated_chord_angle(m, ratio * c, spacing, converged) * deg;
    EXPECT_TRUE(converged) << "l/c = " << ratio;
    EXPECT_NEAR(simulated, elastica_chord_angle(ratio) * deg, 1.0) << "l/c = " << ratio;
  }
  // Read as the standard does: the overhang at which the chord reaches 41.5° is 2c.
  bool converged = false;
  const double measured = peirce_bending_length(m, spacing, 1.5 * c, 2.5 * c, converged);
  EXPECT_TRUE(converged);
  EXPECT_NEAR(measured, c, 0.05 * c);
  RecordProperty("bending_length_error", std::to_string(measured / c - 1.0));
}

TEST(FabricPictureFrame, FrameForceFollowsTheShearCurve) {
  // A square sheet whose border follows a picture frame sheared by γ (sides keep their length,
  // the corner angle closes by γ), the inside free. The frame's generalized force dE/dγ must be
  // the sheet's area times the shear curve's force per unit width, T_s(γ)·A.
  ClothMaterial m = kes_material(test_fabric(), "test fabric");
  m.shear = MeasuredCurve({0.0, 0.05, 0.1, 0.2}, {0.0, 3.0, 5.0, 12.0}, MeasuredCurve::BelowZero::mirror, 0.0, "shear");
  const double side = 0.1;
  for (double gamma : {0.02, 0.07, 0.15}) {
    bool converged = false;
    const double force = picture_frame_force(m, side, gamma, converged);
    EXPECT_TRUE(converged);
    const double expected = side * side * m.shear.value(gamma);
    EXPECT_NEAR(force, expected, 0.02 * expected) << "γ = " << gamma;
  }
}

/// The KES shear cycle (±8°) on a 10 cm picture frame, read at 0.5° and at 5° with steps of
/// `step` [rad]: the loop's widths there and the rise of its mean per radian, per unit area
/// (N/m, N/m per rad).
struct ShearLoops {
  double width_small = 0.0, width_large = 0.0, mean_slope = 0.0;
};

ShearLoops shear_loops(const ClothMaterial& m, double step) {
  const double deg = std::numbers::pi / 180.0, area = 0.1 * 0.1;
  bool converged = false;
  const auto [down_small, up_small] = picture_frame_loop(m, 0.1, 8 * deg, step, 0.5 * deg, converged);
  EXPECT_TRUE(converged);
  const auto [down_large, up_large] = picture_frame_loop(m, 0.1, 8 * deg, step, 5 * deg, converged);
  EXPECT_TRUE(converged);
  return {(up_small - down_small) / area, (up_large - down_large) / area,
          (0.5 * (down_large + up_large) - 0.5 * (down_small + up_small)) / (4.5 * deg) / area};
}

/// KES's gf/cm in N/m and G (gf/(cm·°)) in N/m per radian.
constexpr double kGfPerCm = kGramForce / 1e-2;
double shear_slope(const KesFabric& kes) { return 0.5 * (kes.warp.g + kes.weft.g) * kGfPerCm * 180.0 / std::numbers::pi; }

TEST(FabricPictureFrame, ShearLoopIsAsWideAs2HGAndItsMeanFollowsG) {
  // The KES shear test (±8°): with 2HG given, the loop's width at 0.5° is 2HG and its mean
  // rises with the slope G between 0.5° and 5° (KES reads G there). The sheet shears
  // homogeneously, so every triangle's friction has slipped to ±H by 0.5° after turning at
  // ∓8° (its stick angle is 0.1°): the width holds to the balance's tolerance (1e-10 of the
  // forces), 1e-6 here.
  KesFabric kes = test_fabric();
  kes.warp.hg = 2.2;
  kes.weft.hg = 1.8;
  const double width = 0.5 * (2.2 + 1.8) * kGfPerCm, g = shear_slope(kes);  // 2HG [N/m], G
  const ShearLoops loops = shear_loops(kes_material(kes, "test fabric"), 0.5 * std::numbers::pi / 180.0);
  EXPECT_NEAR(loops.width_small, width, 1e-6 * width);
  EXPECT_NEAR(loops.mean_slope, g, 1e-6 * g);
  // The one width the model has: at 5° the loop is 2HG wide too (KES's 2HG5 is not matched).
  EXPECT_NEAR(loops.width_large, width, 1e-6 * width);
}

TEST(FabricPictureFrame, ShearLoopIsAsWideAs2HGAt05DegreesAnd2HG5At5) {
  // With 2HG5 given too, the friction's strength grows linearly with the shear between the
  // two: the loop of the same ±8° cycle is 2HG wide at 0.5° and 2HG5 wide at 5°. The
  // strength is the held stick angle's: reading a branch at θ, arrived from θ ± s in steps
  // of s, its stick angle is θ ± (s + 0.1°). The two branches' strengths average to H(θ) where
  // both stick angles have the sign of θ (H is linear in |γ_s|): steps of 0.25° keep them
  // there at 0.5° (0.5° steps put one at −0.1°); then 1e-6 as above.
  KesFabric kes = test_fabric();
  kes.warp.hg = 2.2;
  kes.weft.hg = 1.8;
  kes.warp.hg5 = 4.4;
  kes.weft.hg5 = 3.8;
  const double width = 0.5 * (2.2 + 1.8) * kGfPerCm, width_5 = 0.5 * (4.4 + 3.8) * kGfPerCm, g = shear_slope(kes);
  const ShearLoops loops = shear_loops(kes_material(kes, "test fabric"), 0.25 * std::numbers::pi / 180.0);
  EXPECT_NEAR(loops.width_small, width, 1e-6 * width);
  EXPECT_NEAR(loops.width_large, width_5, 1e-6 * width_5);
  // The loop's mean still rises at G: both branches' friction shifts it by the same amount.
  EXPECT_NEAR(loops.mean_slope, g, 1e-6 * g);
}

TEST(FabricEnergy, ReleasedUndampedFabricGainsNoEnergy) {
  // A sheet clamped at its top edge, released swung out of its plane under gravity, without
  // damping: it swings and flexes, and implicit Euler may only lose energy.
  const ClothMaterial m = kes_material(test_fabric(), "test fabric");
  Hang h = hanging_strip(m, 0.1, 0.1, 0.01);
  h.body.settings.cg_tolerance = 1e-10;
  for (Eigen::Index n = 0; n < h.state.x.size() / 3; ++n) {  // swung 0.3 rad about its top edge
    const double depth = -h.state.x[3 * n + 2];
    h.state.x[3 * n + 1] = depth * std::sin(0.3);
    h.state.x[3 * n + 2] = -depth * std::cos(0.3);
  }
  auto total = [&] { return kinetic_energy(h.body, h.state) + potential_energy(h.body, h.state); };
  double energy = total();
  const double start = energy;
  for (int k = 0; k < 400; ++k) {
    step(h.body, h.state, 1e-3);
    const double next = total();
    ASSERT_LE(next, energy + 1e-9 * std::abs(start)) << "step " << k;
    energy = next;
  }
  EXPECT_LT(energy, start);
}

}  // namespace
}  // namespace tactus::physics
