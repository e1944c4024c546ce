#include "contact/hertz.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include "core/counting_allocator.hpp"
#include "core/error.hpp"

namespace tactus::contact {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// Silicone-rubber finger sphere on soft tissue (seed 000 §3.1).
HertzParameters finger_on_tissue() {
  HertzParameters p;
  p.finger_radius = 0.008;
  p.finger = {2.0e6, 0.48};
  p.tissue = {20.0e3, 0.45};
  return p;
}

/// ∫ p dA over the contact disc by the midpoint rule on `rings` annuli.
double integrate_pressure(const HertzContactState& s, int rings) {
  const double dr = s.contact_radius / rings;
  double total = 0.0;
  for (int i = 0; i < rings; ++i) {
    const double r = (i + 0.5) * dr;
    total += s.pressure_at(r) * 2.0 * std::numbers::pi * r * dr;
  }
  return total;
}

TEST(Hertz, HandComputedCase) {
  // E* = 1 / (2·(1 − 0)/1e5) = 5e4 Pa; R = R_f = 0.01 m on flat tissue; d = 0.1 mm:
  // F = 4/3 · 5e4 · √0.01 · (1e-4)^{3/2} = 6.6667e-3 N, a = √(R·d) = 1 mm, p0 = 3183.1 Pa.
  HertzParameters p;
  p.finger_radius = 0.01;
  p.finger = {1e5, 0.0};
  p.tissue = {1e5, 0.0};
  const HertzContact contact(p);
  EXPECT_DOUBLE_EQ(contact.effective_modulus(), 5e4);
  const HertzContactState s = contact.evaluate(1e-4, 0.0);
  EXPECT_EQ(s.regime, HertzRegime::hertz);
  EXPECT_NEAR(s.force, 6.666666666666667e-3, 1e-15);
  EXPECT_NEAR(s.contact_radius, 1e-3, 1e-15);
  EXPECT_NEAR(s.peak_pressure, 3183.0988618379065, 1e-9);
  EXPECT_NEAR(s.stiffness, 2.0 * 5e4 * 1e-3, 1e-9);  // dF/dd = 2·E*·a
}

TEST(Hertz, ForceFollowsTheAnalyticLaw) {
  const HertzParameters p = finger_on_tissue();
  const HertzContact contact(p);
  const double e_star =
      1.0 / ((1 - 0.48 * 0.48) / 2.0e6 + (1 - 0.45 * 0.45) / 20.0e3);  // textbook E*
  EXPECT_NEAR(contact.effective_modulus(), e_star, 1e-9 * e_star);
  const double rf = p.finger_radius;
  for (double kp : {0.0, 1.0 / rf, -0.5 / rf, 50.0, -100.0}) {
    const double radius = 1.0 / (1.0 / rf + kp);
    for (double depth : {1e-5, 3e-4, 1e-3}) {
      const HertzContactState s = contact.evaluate(depth, kp);
      ASSERT_EQ(s.regime, HertzRegime::hertz) << kp << " " << depth;
      const double expected = 4.0 / 3.0 * e_star * std::sqrt(radius) * std::pow(depth, 1.5);
      EXPECT_NEAR(s.force, expected, 1e-12 * expected) << kp << " " << depth;
      EXPECT_NEAR(s.force, hertz_force(e_star, radius, depth), 1e-12 * expected);
      EXPECT_NEAR(s.contact_radius, std::sqrt(radius * depth), 1e-12);
      EXPECT_NEAR(s.effective_curvature, 1.0 / radius, 1e-9 / radius);
      // Seed 000 eq. 3: a = (3·F·R / (4·E*))^{1/3}.
      EXPECT_NEAR(s.contact_radius, std::cbrt(3.0 * s.force * radius / (4.0 * e_star)), 1e-12);
    }
  }
}

TEST(Hertz, LayerStiffeningMatchesDimitriadisPrintedSeries) {
  // Dimitriadis et al. 2002 print the series at ν = 0.5 (their eq. 12 and the unbonded
  // form): bonded 1 + 1.133χ + 1.283χ² + 0.769χ³ + 0.0975χ⁴, sliding 1 + 0.884χ + 0.781χ² +
  // 0.386χ³ + 0.0048χ⁴. Their general eq. 11 with the bonded α₀, β₀ gives −0.0975 for the
  // last term; the function follows eq. 11, so the bonded check allows that term's sign.
  EXPECT_DOUBLE_EQ(layer_stiffening(0.5, 0.0, true), 1.0);
  for (const double chi : {0.1, 0.3, 0.6, 1.0}) {
    const double bonded = 1 + 1.133 * chi + 1.283 * chi * chi + 0.769 * chi * chi * chi;
    EXPECT_NEAR(layer_stiffening(0.5, chi, true), bonded - 0.0975 * std::pow(chi, 4), 1e-3 * bonded) << chi;
    const double sliding = 1 + 0.884 * chi + 0.781 * chi * chi + 0.386 * chi * chi * chi + 0.0048 * std::pow(chi, 4);
    EXPECT_NEAR(layer_stiffening(0.5, chi, false), sliding, 1e-3 * sliding) << chi;
  }
  // A bonded layer is stiffer than one sliding on its base, and both grow with χ.
  EXPECT_GT(layer_stiffening(0.45, 0.5, true), layer_stiffening(0.45, 0.5, false));
  EXPECT_GT(layer_stiffening(0.3, 0.4, false), layer_stiffening(0.3, 0.2, false));
}

TEST(Fingerpad, DepthIsTheInverseOfTheForceOnBothBranches) {
  // The exponential below max_exponential_depth (3 mm), its tangent beyond.
  const FingerpadLaw law;
  for (const double d : {1e-5, 1e-4, 1e-3, 2.9e-3, 3e-3, 4e-3, 1e-2})
    EXPECT_NEAR(law.depth(law.force(d)), d, 1e-12 * d) << d;
  EXPECT_EQ(law.depth(0.0), 0.0);
  EXPECT_EQ(law.depth(-1.0), 0.0);
  EXPECT_EQ(law.depth(std::numeric_limits<double>::quiet_NaN()), 0.0);
}

TEST(Hertz, PunchOnALayerMeetsItsLimits) {
  // A half-space: Sneddon's law, κ = 1.
  EXPECT_DOUBLE_EQ(punch_layer_factor(0.3, 0.0), 1.0);
  // A thick layer (a ≪ h): κ = 1 + cλ + c²λ² + O(λ³), λ = a/h, c = (2/π)∫₀^∞ M, the same
  // first-order term as Dimitriadis et al.'s sphere series on a bonded layer (2002, eq. 11),
  // −2α₀/π. Their α₀ is a quadratic fit in ν; 1 % covers the fit.
  for (const double nu : {0.3, 0.4, 0.45, 0.5}) {
    const double c = 2.0 / std::numbers::pi * (1.2876 - 1.4678 * nu + 1.3442 * nu * nu) / (1.0 - nu);
    const double lambda = 0.01;
    const double slope = (punch_layer_factor(nu, lambda) - 1.0) / lambda;
    EXPECT_NEAR(slope, c * (1.0 + c * lambda), 0.01 * c) << nu;
  }
  // A thin compressible layer (a ≫ h): the layer under the punch is compressed with no room
  // to spread, F → π a² d (λ + 2μ)/h, so κ → (π/2)(a/h)(1 − ν)²/(1 − 2ν), with an edge
  // correction falling as h/a: (κ/κ∞ − 1)·a/h settles to a constant (measured +0.25 at
  // ν = 0.3, −0.22 at ν = 0.4: the edge adds stiffness or relieves it).
  for (const double nu : {0.3, 0.4}) {
    const auto ratio = [nu](double lambda) {
      return punch_layer_factor(nu, lambda) / (std::numbers::pi / 2.0 * lambda * (1 - nu) * (1 - nu) / (1 - 2 * nu));
    };
    const double r8 = ratio(8.0), r16 = ratio(16.0);
    EXPECT_NEAR(r16, 1.0, 0.03) << nu;
    EXPECT_NEAR((r16 - 1.0) * 16.0, (r8 - 1.0) * 8.0, 0.1 * std::abs(r8 - 1.0) * 8.0) << nu;
  }
  // A thin incompressible layer: the squeeze flow between a sliding punch and a bonded base,
  // p = 3Gd(a² − r²)/(4h³), F = 3πGda⁴/(8h³), so κ → 3πλ³/64, approached slowly from above.
  double before = 1e9;
  for (const double lambda : {4.0, 8.0, 16.0}) {
    const double ratio = punch_layer_factor(0.5, lambda) / (3.0 * std::numbers::pi * std::pow(lambda, 3) / 64.0);
    EXPECT_GT(ratio, 1.0) << lambda;
    EXPECT_LT(ratio, before) << lambda;
    before = ratio;
  }
  EXPECT_LT(before, 1.5);
  // Stiffer as the layer thins, and stiffer as it grows less compressible.
  EXPECT_GT(punch_layer_factor(0.3, 1.0), punch_layer_factor(0.3, 0.5));
  EXPECT_GT(punch_layer_factor(0.45, 1.0), punch_layer_factor(0.3, 1.0));
  EXPECT_THROW((void)punch_layer_factor(0.6, 1.0), InputError);
  EXPECT_THROW((void)punch_layer_factor(0.3, 25.0), InputError);
  EXPECT_THROW((void)punch_layer_factor(0.3, std::nan("")), InputError);
}

TEST(Hertz, FlatTissueUsesTheFingerRadius) {
  const HertzContact contact(finger_on_tissue());
  const double rf = contact.parameters().finger_radius;
  const HertzContactState s = contact.evaluate(5e-4, 0.0);
  EXPECT_DOUBLE_EQ(s.effective_curvature, 1.0 / rf);
  EXPECT_NEAR(s.force, hertz_force(contact.effective_modulus(), rf, 5e-4), 1e-14);
  EXPECT_DOUBLE_EQ(contact.max_contact_radius(0.0), rf);
}

TEST(Hertz, PressureIntegratesToTheForce) {
  const HertzContact contact(finger_on_tissue());
  const double rf = contact.parameters().finger_radius;
  struct Case {
    double depth, kp;
    HertzRegime regime;
  };
  for (const Case& c : {Case{1e-5, 0.0, HertzRegime::hertz}, Case{2e-3, 100.0, HertzRegime::hertz},
                        Case{3e-3, 2.0 / rf, HertzRegime::saturated}, Case{0.012, 0.0, HertzRegime::saturated},
                        Case{1e-3, -1.0 / rf, HertzRegime::conformal}, Case{1e-3, -3.0 / rf, HertzRegime::conformal}}) {
    const HertzContactState s = contact.evaluate(c.depth, c.kp);
    SCOPED_TRACE(::testing::Message() << "depth " << c.depth << " kp " << c.kp);
    EXPECT_EQ(s.regime, c.regime);
    ASSERT_GT(s.force, 0.0);
    EXPECT_NEAR(s.peak_pressure, 3.0 * s.force / (2.0 * std::numbers::pi * s.contact_radius * s.contact_radius),
                1e-9 * s.peak_pressure);
    EXPECT_NEAR(integrate_pressure(s, 2000) / s.force, 1.0, 0.005);
    EXPECT_DOUBLE_EQ(s.pressure_at(0.0), s.peak_pressure);
    EXPECT_EQ(s.pressure_at(s.contact_radius), 0.0);
    EXPECT_EQ(s.pressure_at(1.5 * s.contact_radius), 0.0);
    EXPECT_NEAR(s.pressure_at(0.6 * s.contact_radius), 0.8 * s.peak_pressure, 1e-9 * s.peak_pressure);
  }
  // Coarse rings converge toward F: the check can tell a wrong profile from a right one.
  const HertzContactState s = contact.evaluate(1e-4, 0.0);
  EXPECT_LT(std::abs(integrate_pressure(s, 2000) / s.force - 1.0), std::abs(integrate_pressure(s, 10) / s.force - 1.0));
}

TEST(Hertz, ContinuousAndMonotoneAcrossTheConformalBoundary) {
  const HertzContact contact(finger_on_tissue());
  const double rf = contact.parameters().finger_radius;
  const double e_star = contact.effective_modulus();
  const double boundary = -1.0 / rf;
  for (double depth : {1e-5, 1e-4, 1e-3, 5e-3}) {
    // F(kp) is non-increasing with a slope no steeper than (2/3)·E*·a_max³ (its value on
    // the saturated branch), so steps of h change F by at most that times h.
    const double max_slope = 2.0 / 3.0 * e_star * rf * rf * rf;
    const double h = 0.05;  // 1/m
    double previous = contact.evaluate(depth, boundary - 200.0).force;
    for (double kp = boundary - 200.0 + h; kp <= boundary + 200.0; kp += h) {
      const HertzContactState s = contact.evaluate(depth, kp);
      ASSERT_TRUE(std::isfinite(s.force) && std::isfinite(s.stiffness) && std::isfinite(s.peak_pressure));
      ASSERT_TRUE(std::isfinite(s.contact_radius) && std::isfinite(s.effective_curvature));
      ASSERT_LE(s.force, previous * (1.0 + 1e-12)) << depth << " " << kp;
      ASSERT_LE(previous - s.force, max_slope * h * 1.001) << depth << " " << kp;
      previous = s.force;
    }
    // At and beyond the boundary: a flat punch of the finger's radius.
    for (double kp : {boundary, boundary - 1.0, boundary - 1e5}) {
      const HertzContactState s = contact.evaluate(depth, kp);
      EXPECT_EQ(s.regime, HertzRegime::conformal);
      EXPECT_NEAR(s.force, 2.0 * e_star * rf * depth, 1e-9 * s.force);
      EXPECT_EQ(s.effective_curvature, 0.0);
      EXPECT_DOUBLE_EQ(s.contact_radius, rf);
    }
    // One-sided slopes at the boundary are finite and match their analytic values.
    const double step = 1e-3;
    const double right = (contact.evaluate(depth, boundary + step).force - contact.evaluate(depth, boundary).force) / step;
    const double left = (contact.evaluate(depth, boundary).force - contact.evaluate(depth, boundary - step).force) / step;
    EXPECT_NEAR(right, -max_slope, 1e-3 * max_slope);
    EXPECT_EQ(left, 0.0);
  }
}

TEST(Hertz, SaturationContinuesAlongTheTangent) {
  const HertzContact contact(finger_on_tissue());
  const double rf = contact.parameters().finger_radius;
  const double e_star = contact.effective_modulus();
  for (double kp : {2.0 / rf, 0.0, -0.5 / rf}) {
    const double a_max = contact.max_contact_radius(kp);
    const double curvature = 1.0 / rf + kp;
    const double saturation = a_max * a_max * curvature;
    const HertzContactState below = contact.evaluate(saturation * (1 - 1e-9), kp);
    const HertzContactState above = contact.evaluate(saturation * (1 + 1e-9), kp);
    EXPECT_EQ(below.regime, HertzRegime::hertz);
    EXPECT_EQ(above.regime, HertzRegime::saturated);
    EXPECT_NEAR(below.force, above.force, 1e-7 * above.force);
    EXPECT_NEAR(below.stiffness, above.stiffness, 1e-7 * above.stiffness);
    EXPECT_NEAR(below.contact_radius, a_max, 1e-8 * a_max);
    // Beyond: F(d) = F(d*) + 2·E*·a_max·(d − d*).
    const double d = 3.0 * saturation;
    const HertzContactState far = contact.evaluate(d, kp);
    EXPECT_NEAR(far.force, hertz_force(e_star, 1.0 / curvature, saturation) + 2 * e_star * a_max * (d - saturation),
                1e-9 * far.force);
  }
  // Convex tissue: the limit is Hertz's own d ≤ R.
  const double kp = 1.0 / rf;  // R = R_f / 2
  EXPECT_DOUBLE_EQ(contact.max_contact_radius(kp), rf / 2.0);
  EXPECT_EQ(contact.evaluate(0.99 * rf / 2.0, kp).regime, HertzRegime::hertz);
  EXPECT_EQ(contact.evaluate(1.01 * rf / 2.0, kp).regime, HertzRegime::saturated);
  // Force grows with depth everywhere.
  double previous = 0.0;
  for (double d = 1e-6; d < 0.05; d *= 1.1) {
    const double f = contact.evaluate(d, -0.9 / rf).force;
    EXPECT_GT(f, previous);
    previous = f;
  }
}

TEST(Hertz, NoContactAndBadNumbersGiveNoForce) {
  const HertzContact contact(finger_on_tissue());
  for (double depth : {0.0, -1e-3, kNaN, kInf, -kInf}) {
    const HertzContactState s = contact.evaluate(depth, 0.0);
    EXPECT_EQ(s.regime, HertzRegime::none);
    EXPECT_EQ(s.force, 0.0);
    EXPECT_EQ(s.pressure_at(0.0), 0.0);
  }
  const HertzContactState flat = contact.evaluate(1e-3, 0.0);
  for (double kp : {kNaN, kInf, -kInf, 1e300, -1e300}) {
    const HertzContactState s = contact.evaluate(1e-3, kp);
    EXPECT_TRUE(std::isfinite(s.force) && std::isfinite(s.peak_pressure) && std::isfinite(s.stiffness)) << kp;
    EXPECT_GE(s.force, 0.0);
    if (std::isnan(kp)) {
      EXPECT_EQ(s.force, flat.force);
    }
  }
}

TEST(Friction, BoundedByMuNAndOpposesTheSlip) {
  const CoulombFriction friction({0.4, 1e-3});
  std::mt19937 rng(7);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::uniform_real_distribution<double> load(0.0, 5.0);
  for (int i = 0; i < 2000; ++i) {
    const Vec3 normal = Vec3(gauss(rng), gauss(rng), gauss(rng)).normalized();
    const Vec3 slip = Vec3(gauss(rng), gauss(rng), gauss(rng)) * std::pow(10.0, gauss(rng) - 2.0);
    const double n = load(rng);
    const Vec3 f = friction.force(slip, normal, n);
    const Vec3 tangential = slip - slip.dot(normal) * normal;
    ASSERT_LE(f.norm(), 0.4 * n * (1 + 1e-12));
    EXPECT_LE(f.dot(tangential), 0.0);
    EXPECT_NEAR(f.dot(normal), 0.0, 1e-12 * (1 + f.norm()));
    EXPECT_NEAR(f.normalized().dot(tangential.normalized()), -1.0, 1e-9);
  }
  // Fast slip: full Coulomb friction; slow slip: proportionally less; none at rest.
  const Vec3 z = Vec3::UnitZ();
  EXPECT_NEAR(friction.force(Vec3(1.0, 0, 0), z, 2.0).x(), -0.8, 1e-6);
  EXPECT_NEAR(friction.force(Vec3(1e-6, 0, 0), z, 2.0).x(), -0.8 * 1e-3, 1e-8);
  EXPECT_EQ(friction.force(Vec3::Zero(), z, 2.0), Vec3::Zero());
  EXPECT_EQ(friction.force(Vec3(0, 0, 3.0), z, 2.0), Vec3::Zero());  // pulling off, no slip
  EXPECT_EQ(friction.force(Vec3(1, 0, 0), z, kNaN), Vec3::Zero());
  EXPECT_EQ(friction.force(Vec3(kNaN, 0, 0), z, 1.0), Vec3::Zero());
  EXPECT_TRUE(friction.force(Vec3(1e300, 1e300, 0), z, 1.0).allFinite());
}

TEST(SphereContact, SumsContactFrictionAndAmbient) {
  const HertzContact contact(finger_on_tissue());
  const CoulombFriction friction({0.5, 1e-4});
  SphereContactInput in;
  in.depth = 1e-3;
  in.tissue_mean_curvature = 30.0;
  in.normal = Vec3(0, 0, 2.0);  // not unit: normalised
  in.slip_velocity = Vec3(0.05, 0, -0.01);
  in.weight_load = 0.02;
  in.ambient_force = Vec3(0, 0, -0.3);
  const SphereContactForce f = sphere_contact_force(contact, friction, in);
  const double fc = contact.evaluate(1e-3, 30.0).force;
  EXPECT_NEAR(f.contact.z(), fc, 1e-15);
  EXPECT_EQ(f.contact.head<2>(), Eigen::Vector2d::Zero());
  EXPECT_NEAR(f.friction.x(), -0.5 * (fc + 0.02) * 0.05 / std::hypot(0.05, 1e-4), 1e-12);
  EXPECT_EQ(f.friction.z(), 0.0);
  EXPECT_EQ(f.ambient, in.ambient_force);
  EXPECT_TRUE(f.total.isApprox(f.contact + f.friction + f.ambient));
  EXPECT_EQ(f.hertz.force, fc);

  // Out of contact only the ambient force remains; bad numbers never leak out.
  in.depth = -1e-3;
  const SphereContactForce apart = sphere_contact_force(contact, friction, in);
  EXPECT_EQ(apart.total, in.ambient_force);
  in.depth = 1e-3;
  in.normal = Vec3(kNaN, 0, 0);
  in.ambient_force = Vec3(kInf, 0, 0);
  const SphereContactForce broken = sphere_contact_force(contact, friction, in);
  EXPECT_TRUE(broken.total.allFinite());
  EXPECT_EQ(broken.total, Vec3::Zero());
}

TEST(Fingerpad, MatchesHandComputedValues) {
  const FingerpadLaw law;  // b = 190 N/m, m = 2100 1/m
  // (190/2100)·(e^{2100·d} − 1):
  EXPECT_NEAR(law.force(0.5e-3), 0.168073196396191, 1e-12);
  EXPECT_NEAR(law.force(1e-3), 0.6483677539942161, 1e-12);
  EXPECT_NEAR(law.force(2e-3), 5.9430489989408475, 1e-11);
  EXPECT_NEAR(law.stiffness(1e-3), 1551.5722833878538, 1e-9);
  EXPECT_DOUBLE_EQ(law.stiffness(0.0), 190.0);
  EXPECT_NEAR(law.force(1e-9), 190.0 * 1e-9, 1e-12);  // linear start: slope b
  EXPECT_EQ(law.force(0.0), 0.0);
  EXPECT_EQ(law.force(-1e-3), 0.0);
  EXPECT_EQ(law.force(kNaN), 0.0);
  // Past the exponential range: the tangent, continuous in value and slope.
  const double d_max = law.parameters().max_exponential_depth;
  EXPECT_NEAR(law.force(d_max * (1 + 1e-12)), law.force(d_max), 1e-9);
  EXPECT_NEAR(law.force(d_max + 1e-3), law.force(d_max) + law.stiffness(d_max) * 1e-3, 1e-9);
  EXPECT_TRUE(std::isfinite(law.force(10.0)));
}

TEST(Qlv, StepRelaxesWithTheRightTimeConstant) {
  QuasiLinearViscoelastic qlv({0.5, {{0.5, 0.1}}});
  const double dt = 1e-3, f0 = 2.0;
  qlv.step(f0, dt);  // the step, spread over one sample
  // After it the excess over g∞·F_e decays as e^{−t/τ}: one τ later it is 1/e as large.
  const double excess0 = qlv.force() - 0.5 * f0;
  for (int i = 0; i < 100; ++i) qlv.step(f0, dt);
  EXPECT_NEAR((qlv.force() - 0.5 * f0) / excess0, std::exp(-1.0), 1e-12);
  for (int i = 0; i < 5000; ++i) qlv.step(f0, dt);
  EXPECT_NEAR(qlv.force(), 0.5 * f0, 1e-12);
}

TEST(Qlv, MatchesTheAnalyticResponse) {
  const ReducedRelaxation g = fingerpad_relaxation();
  EXPECT_NEAR(g.at(0.0), 1.0, 1e-12);
  const double dt = 1e-4, f0 = 1.5;
  // Step: F_e jumps within the first sample; exact for that one-sample ramp:
  // F(t) = g∞·F0 + Σ g_i·F0·(τ_i/Δt)(1 − e^{−Δt/τ_i})·e^{−(t − Δt)/τ_i}.
  QuasiLinearViscoelastic qlv(g);
  for (int n = 1; n <= 30000; ++n) {  // 3 s
    const double f = qlv.step(f0, dt);
    if (n % 97 != 1) continue;
    const double t = n * dt;
    double expected = g.steady_state * f0;
    for (const auto& term : g.terms)
      expected += term.weight * f0 * term.time_constant / dt * (1 - std::exp(-dt / term.time_constant)) *
                  std::exp(-(t - dt) / term.time_constant);
    ASSERT_NEAR(f, expected, 1e-10 * f0) << t;
    // And close to the ideal step response F0·G(t) (the one-sample spread costs ≈ Δt/2τ).
    ASSERT_NEAR(f, f0 * g.at(t - dt / 2), 2e-3 * f0) << t;
  }
  // Fully relaxed: g∞·F_e.
  for (int n = 0; n < 200000; ++n) qlv.step(f0, dt);  // 20 s more
  EXPECT_NEAR(qlv.force(), g.steady_state * f0, 1e-6 * f0);

  // Ramp and hold: F_e = F0·t/T up to T, then held.
  QuasiLinearViscoelastic ramp(g);
  const double ramp_time = 0.05;
  for (int n = 1; n <= 5000; ++n) {
    const double t = n * dt;
    const double f = ramp.step(f0 * std::min(t / ramp_time, 1.0), dt);
    const double s = std::min(t, ramp_time);
    double expected = g.steady_state * f0 * s / ramp_time;
    for (const auto& term : g.terms)
      expected += term.weight * f0 / ramp_time * term.time_constant * (1 - std::exp(-s / term.time_constant)) *
                  std::exp(-(t - s) / term.time_constant);
    ASSERT_NEAR(f, expected, 1e-10 * f0) << t;
  }
}

TEST(Qlv, FingerpadRampAndHoldRelaxes) {
  const FingerpadLaw law;
  QuasiLinearViscoelastic qlv(fingerpad_relaxation());
  const double dt = 1e-3;
  double peak = 0.0, previous = 0.0;
  for (int n = 1; n <= 4000; ++n) {
    const double depth = 1.5e-3 * std::min(n * dt / 0.1, 1.0);  // 100 ms ramp to 1.5 mm
    const double f = qlv.step(law.force(depth), dt);
    EXPECT_LE(f, law.force(depth) * (1 + 1e-12));  // G ≤ 1: never above the elastic response
    if (n * dt > 0.1 + 1e-9) {
      EXPECT_LT(f, previous);  // relaxing during the hold
    }
    peak = std::max(peak, f);
    previous = f;
  }
  const double relaxed = fingerpad_relaxation().steady_state * law.force(1.5e-3);
  EXPECT_GT(previous, relaxed);
  EXPECT_LT(previous, 1.05 * relaxed);  // 3.9 s ≈ 2.8 τ₃ into the hold
  EXPECT_GT(peak, 1.5 * relaxed);

  // Reset: fully relaxed at the given elastic force; bad numbers leave the state alone.
  qlv.reset(1.0);
  EXPECT_DOUBLE_EQ(qlv.force(), 0.45);
  EXPECT_DOUBLE_EQ(qlv.step(kNaN, dt), 0.45);
  EXPECT_DOUBLE_EQ(qlv.step(1.0, kNaN), 0.45);
  EXPECT_DOUBLE_EQ(qlv.step(2.0, -1.0), 0.45 * 2.0 + 0.55 * 1.0);  // dt = 0: instantaneous, G(0) = 1
}

TEST(ContactLaws, EvaluationAllocatesNothing) {
  const HertzContact contact(finger_on_tissue());
  const CoulombFriction friction({0.3, 1e-3});
  const FingerpadLaw law;
  QuasiLinearViscoelastic qlv(fingerpad_relaxation());
  SphereContactInput in;
  in.slip_velocity = Vec3(0.01, 0.0, 0.0);
  double sum = 0.0;
  const tactus::testing::AllocationCounter counter;
  for (int i = 0; i < 1000; ++i) {
    in.depth = 1e-5 * i;
    in.tissue_mean_curvature = -200.0 + 0.5 * i;
    sum += sphere_contact_force(contact, friction, in).total.norm();
    sum += contact.evaluate(in.depth, in.tissue_mean_curvature).pressure_at(1e-4);
    sum += qlv.step(law.force(in.depth), 1e-3);
  }
  EXPECT_EQ(counter.count(), 0u);
  EXPECT_GT(sum, 0.0);
}

TEST(ContactLaws, RejectBadParameters) {
  HertzParameters p = finger_on_tissue();
  p.finger_radius = 0.0;
  EXPECT_THROW(HertzContact{p}, InputError);
  p = finger_on_tissue();
  p.tissue.youngs_modulus = -1.0;
  EXPECT_THROW(HertzContact{p}, InputError);
  p = finger_on_tissue();
  p.finger.poisson_ratio = 0.6;
  try {
    HertzContact{p};
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("finger: Poisson"), std::string::npos) << e.what();
  }
  p.finger.poisson_ratio = kNaN;
  EXPECT_THROW(HertzContact{p}, InputError);

  EXPECT_THROW(CoulombFriction({-0.1, 1e-3}), InputError);
  EXPECT_THROW(CoulombFriction({0.1, 0.0}), InputError);
  EXPECT_THROW(CoulombFriction({kInf, 1e-3}), InputError);

  EXPECT_THROW(FingerpadLaw({0.0, 2100.0, 3e-3}), InputError);
  EXPECT_THROW(FingerpadLaw({190.0, -1.0, 3e-3}), InputError);
  EXPECT_THROW(FingerpadLaw({190.0, 2100.0, 1.0}), InputError);  // e^{2100} overflows

  EXPECT_THROW(QuasiLinearViscoelastic({0.5, {{0.4, 0.1}}}), InputError);   // sums to 0.9
  EXPECT_THROW(QuasiLinearViscoelastic({0.5, {{0.5, 0.0}}}), InputError);   // τ = 0
  EXPECT_THROW(QuasiLinearViscoelastic({1.5, {{-0.5, 0.1}}}), InputError);  // negative weight
  ReducedRelaxation many{0.3, {}};
  for (int i = 0; i < 7; ++i) many.terms.push_back({0.1, 0.01 * (i + 1)});
  EXPECT_THROW(QuasiLinearViscoelastic{many}, InputError);
}

}  // namespace
}  // namespace tactus::contact
