#include "lod/selection.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>

#include "core/error.hpp"
#include "lod/impostors.hpp"
#include "mesh/generators.hpp"

namespace tactus::lod {
namespace {

/// Every combination of levels within the budget; the least benefit-weighted error (ties
/// to the lower cost).
Selection brute_force(const std::vector<ObjectLevels>& objects, double budget) {
  std::vector<std::size_t> level(objects.size(), 0);
  Selection best;
  best.weighted_error = std::numeric_limits<double>::infinity();
  for (;;) {
    const Selection s = evaluate_selection(objects, level, budget);
    if (s.within_budget && (s.weighted_error < best.weighted_error ||
                            (s.weighted_error == best.weighted_error && s.cost < best.cost)))
      best = s;
    std::size_t i = 0;
    while (i < objects.size() && ++level[i] == objects[i].levels.size()) level[i++] = 0;
    if (i == objects.size()) break;
  }
  return best;
}

TEST(Selection, GreedyIsOptimalWithUnitStepsAndConvexErrors) {
  // Each step finer costs one unit and removes less error than the step before (convex
  // errors): a separable convex allocation, for which taking the best marginal gain
  // first is optimal.
  std::mt19937_64 random(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int trial = 0; trial < 300; ++trial) {
    const auto n = static_cast<std::size_t>(1 + random() % 4);
    std::vector<ObjectLevels> objects(n);
    double base = 0.0;
    for (ObjectLevels& o : objects) {
      const auto levels = static_cast<std::size_t>(1 + random() % 4);
      o.benefit = unit(random) * 10.0;
      const double start_cost = std::floor(unit(random) * 4.0);
      base += start_cost;
      // Drops d_0 > d_1 > … between consecutive levels, e_l = floor + Σ_{m ≥ l} d_m.
      std::vector<double> drops(levels, 0.0);
      double drop = 0.5 + unit(random);
      for (std::size_t l = 0; l + 1 < levels; ++l) {
        drops[l] = drop;
        drop *= 0.2 + 0.7 * unit(random);
      }
      double error = 0.1 * unit(random);
      std::vector<double> errors(levels);
      for (std::size_t l = levels; l-- > 0;) errors[l] = (error += drops[l]);
      for (std::size_t l = 0; l < levels; ++l) o.levels.push_back({start_cost + static_cast<double>(l), errors[l]});
    }
    const double budget = base + static_cast<double>(random() % 8);
    const Selection greedy = select_levels(objects, budget);
    const Selection best = brute_force(objects, budget);
    EXPECT_TRUE(greedy.within_budget);
    EXPECT_LE(greedy.cost, budget);
    EXPECT_NEAR(greedy.weighted_error, best.weighted_error, 1e-12) << "trial " << trial;
  }
}

TEST(Selection, GreedyStaysWithinBudgetIsDeterministicAndNeverWorseThanTheCoarsest) {
  std::mt19937_64 random(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int optimal = 0;
  constexpr int kTrials = 500;
  for (int trial = 0; trial < kTrials; ++trial) {
    const auto n = static_cast<std::size_t>(1 + random() % 5);
    std::vector<ObjectLevels> objects(n);
    double coarsest_cost = 0.0, finest_cost = 0.0;
    for (ObjectLevels& o : objects) {
      o.benefit = unit(random);
      double cost = unit(random), error = 1.0 + unit(random);
      const auto levels = static_cast<std::size_t>(1 + random() % 4);
      for (std::size_t l = 0; l < levels; ++l) {
        o.levels.push_back({cost, l + 1 == levels ? 0.0 : error});
        cost += unit(random) * 2.0;
        error *= unit(random);
      }
      coarsest_cost += o.levels.front().cost;
      finest_cost += o.levels.back().cost;
    }
    const double budget = coarsest_cost + unit(random) * (finest_cost - coarsest_cost);
    const Selection a = select_levels(objects, budget);
    const Selection b = select_levels(objects, budget);
    EXPECT_EQ(a.level, b.level);
    EXPECT_EQ(a.cost, b.cost);
    EXPECT_TRUE(a.within_budget);
    EXPECT_LE(a.cost, budget * (1.0 + 1e-12));
    const Selection coarsest = evaluate_selection(objects, std::vector<std::size_t>(n, 0), budget);
    EXPECT_LE(a.weighted_error, coarsest.weighted_error);
    const Selection best = brute_force(objects, budget);
    EXPECT_GE(a.weighted_error, best.weighted_error - 1e-12);
    if (a.weighted_error <= best.weighted_error + 1e-12) ++optimal;
  }
  // Not a guarantee (the general case is a knapsack), but the greedy rule is mostly right.
  EXPECT_GT(optimal, kTrials * 7 / 10);
}

TEST(Selection, TiesGoToTheLowerObjectAndOverBudgetStaysCoarsest) {
  const ObjectLevels twin{{{1.0, 2.0}, {2.0, 0.0}}, 1.0};
  const std::vector<ObjectLevels> objects{twin, twin, twin};
  Selection s = select_levels(objects, 4.0);  // room for one refinement
  EXPECT_EQ(s.level, (std::vector<std::size_t>{1, 0, 0}));
  EXPECT_EQ(s.cost, 4.0);
  EXPECT_EQ(s.weighted_error, 4.0);
  s = select_levels(objects, 2.5);
  EXPECT_FALSE(s.within_budget);
  EXPECT_EQ(s.level, (std::vector<std::size_t>{0, 0, 0}));
  EXPECT_EQ(s.cost, 3.0);
  // The benefit orders the refinements: the nearer object first.
  std::vector<ObjectLevels> weighted{twin, twin};
  weighted[1].benefit = 3.0;
  EXPECT_EQ(select_levels(weighted, 3.0).level, (std::vector<std::size_t>{0, 1}));
  // A refinement that removes no error is never taken; a free one always.
  const std::vector<ObjectLevels> odd{{{{1.0, 1.0}, {1.0, 0.5}, {3.0, 0.5}}, 1.0}};
  EXPECT_EQ(select_levels(odd, 10.0).level, (std::vector<std::size_t>{1}));
  EXPECT_TRUE(select_levels({}, 0.0).within_budget);
}

TEST(Selection, RefusesBadInput) {
  EXPECT_THROW((void)select_levels(std::vector<ObjectLevels>{ObjectLevels{}}, 1.0), InputError);
  EXPECT_THROW((void)select_levels(std::vector<ObjectLevels>{{{{-1.0, 0.0}}, 1.0}}, 1.0), InputError);
  EXPECT_THROW((void)select_levels(std::vector<ObjectLevels>{{{{1.0, 0.0}}, std::nan("")}}, 1.0), InputError);
  EXPECT_THROW((void)select_levels(std::vector<ObjectLevels>{{{{1.0, 0.0}}, 1.0}}, -1.0), InputError);
}

TEST(Selection, BenefitsFollowProjectedSizeAndToolNearness) {
  const Vec3 eye = Vec3::Zero();
  EXPECT_DOUBLE_EQ(graphics_benefit(Vec3(0, 0, -2), 0.5, eye, 800.0), 200.0);
  EXPECT_DOUBLE_EQ(graphics_benefit(Vec3(0, 0, -4), 0.5, eye, 800.0), 100.0);
  EXPECT_DOUBLE_EQ(graphics_benefit(Vec3(0, 0, -0.1), 0.5, eye, 800.0), 800.0);  // eye inside
  EXPECT_EQ(haptic_benefit(-0.001, 0.05), 1.0);
  EXPECT_EQ(haptic_benefit(0.0, 0.05), 1.0);
  EXPECT_DOUBLE_EQ(haptic_benefit(0.025, 0.05), 0.5);
  EXPECT_EQ(haptic_benefit(0.05, 0.05), 0.0);
  EXPECT_EQ(haptic_benefit(1.0, 0.05), 0.0);
}

SwitchParams four_levels() {
  SwitchParams p;
  p.raise_force = 2.0;
  p.lower_force = 1.0;
  p.hold_time = 0.1;
  p.min_dwell = 0.02;
  p.coarsest = 0;
  p.finest = 3;
  return p;
}

TEST(ForceThresholdSwitch, RaisesAtOnceLowersAfterTheHoldTime) {
  ForceThresholdSwitch s(four_levels(), 0);
  std::vector<LevelSwitch> switches;
  for (int k = 0; k <= 1000; ++k) {  // 1 kHz: 3 N for 0.2 s, then 0 N
    const double t = k * 1e-3;
    if (const auto made = s.step(t, t < 0.2 ? 3.0 : 0.0)) switches.push_back(*made);
  }
  ASSERT_EQ(switches.size(), 6U);
  EXPECT_DOUBLE_EQ(switches[0].time, 0.0);
  EXPECT_EQ(switches[0].to, 1U);
  // Within a frame or two: k × 1 ms carries rounding, so a 0.1 s wait may end a frame late.
  EXPECT_NEAR(switches[1].time, 0.02, 2.5e-3);  // one finer per min_dwell
  EXPECT_NEAR(switches[2].time, 0.04, 2.5e-3);
  EXPECT_EQ(switches[2].to, 3U);
  EXPECT_NEAR(switches[3].time, 0.3, 2.5e-3);  // one coarser per hold time below 1 N
  EXPECT_NEAR(switches[4].time, 0.4, 2.5e-3);
  EXPECT_NEAR(switches[5].time, 0.5, 2.5e-3);
  for (std::size_t i = 3; i < 6; ++i) EXPECT_EQ(switches[i].to + 1, switches[i].from);
  EXPECT_EQ(s.level, 0U);
  EXPECT_THROW(ForceThresholdSwitch(SwitchParams{.raise_force = 1.0, .lower_force = 1.0}, 0), InputError);
}

/// Direction changes in a sequence of switches (finer then coarser or back).
int reversals(const std::vector<LevelSwitch>& switches) {
  int count = 0;
  for (std::size_t i = 1; i < switches.size(); ++i)
    if ((switches[i].to > switches[i].from) != (switches[i - 1].to > switches[i - 1].from)) ++count;
  return count;
}

TEST(ForceThresholdSwitch, AForceHoveringAtAThresholdDoesNotFlicker) {
  std::mt19937_64 random(3);
  std::normal_distribution<double> noise(0.0, 0.05);
  for (const double hover : {2.0, 1.0, 1.5}) {
    for (const std::size_t start : {std::size_t{0}, std::size_t{3}}) {
      ForceThresholdSwitch s(four_levels(), start);
      std::vector<LevelSwitch> switches;
      for (int k = 0; k < 3000; ++k) {  // 3 s at 1 kHz with a 7 Hz wobble and noise
        const double t = k * 1e-3;
        const double force = hover + 0.08 * std::sin(2.0 * 3.14159265358979 * 7.0 * t) + noise(random);
        if (const auto made = s.step(t, force)) switches.push_back(*made);
      }
      EXPECT_EQ(reversals(switches), 0) << "hovering at " << hover << " from level " << start;
      EXPECT_LE(switches.size(), 3U);
    }
  }
}

TEST(LevelBlend, WeightsRiseFromZeroToOneOverTheDuration) {
  LevelBlend blend;
  EXPECT_EQ(blend.weight(0.0), 1.0);
  blend.start({0, 1, 1.0});
  EXPECT_EQ(blend.weight(0.999), 0.0);
  EXPECT_EQ(blend.weight(1.0), 0.0);
  EXPECT_NEAR(blend.weight(1.0025), 0.5, 1e-9);
  EXPECT_NEAR(blend.weight(1.005), 1.0, 1e-9);
  EXPECT_EQ(blend.weight(1.0051), 1.0);
  EXPECT_FALSE(blend.active(1.006));
  blend.shape = BlendShape::smoothstep;
  EXPECT_NEAR(blend.weight(1.00125), 0.15625, 1e-9);
  EXPECT_NEAR(blend.weight(1.0025), 0.5, 1e-9);
  const Vec3 f = blend.blend(1.0025, Vec3(2, 0, 0), Vec3(4, 0, 0));
  EXPECT_NEAR(f.x(), 3.0, 1e-9);
}

/// A tool pressing into a sphere's impostor levels at 1 kHz, the force a penalty on the
/// penetration of the current level; the switch picks the level, the blend carries the
/// force across each switch. Returns the largest frame-to-frame force step at a switch,
/// relative to the force there, and counts the switches.
double worst_relative_step(const ImpostorHierarchy& h, double blend_duration, int& switches_made) {
  constexpr double kStiffness = 1000.0;  // N/m
  SwitchParams params = four_levels();
  params.finest = h.levels.size() - 1;
  ForceThresholdSwitch level_switch(params, 0);
  LevelBlend blend;
  blend.duration = blend_duration;
  const auto force_on = [&](std::size_t level, const Vec3& tool) {
    const contact::ClosestSurfacePoint c = h.levels[level].bvh.closest_point_with_side(tool);
    return c.behind ? Vec3(kStiffness * c.distance * c.normal) : Vec3(Vec3::Zero());
  };
  const Vec3 direction = Vec3(0.3, 0.5, 0.81).normalized();
  double previous = 0.0, worst = 0.0;
  switches_made = 0;
  std::optional<double> last_switch;
  for (int k = 0; k <= 2000; ++k) {  // in to 6 mm over 1 s, back out over 1 s
    const double t = k * 1e-3;
    const double depth = 0.006 * (t <= 1.0 ? t : 2.0 - t);
    const Vec3 tool = (0.05 - depth) * direction;
    Vec3 force = force_on(level_switch.level, tool);
    if (blend.active(t) && blend.current) force = blend.blend(t, force_on(blend.current->from, tool), force);
    const double magnitude = force.norm();
    if (const auto made = level_switch.step(t, magnitude)) {
      ++switches_made;
      last_switch = t;
      blend.start(*made);
      // The frame's force is sent before the switch takes effect: the next frame blends.
    }
    // Steps in the frames a switch or a blend touches.
    if (last_switch && t - *last_switch <= blend_duration + 2e-3 && k > 0 && magnitude > 0.0)
      worst = std::max(worst, std::abs(magnitude - previous) / magnitude);
    previous = magnitude;
  }
  return worst;
}

TEST(LevelBlend, TheForceStaysContinuousAcrossSwitchesInAPressSweep) {
  ImpostorParams params;
  params.coarse_levels = 2;
  params.subdivision_levels = 1;
  params.error_samples = 512;
  params.cost_queries = 16;
  const ImpostorHierarchy h = build_impostors(mesh::sphere(0.05, 3), params);
  int switches = 0;
  const double blended = worst_relative_step(h, 0.005, switches);
  EXPECT_GE(switches, 4);  // up through every level and back down
  EXPECT_LE(blended, 0.10);
  int unblended_switches = 0;
  const double unblended = worst_relative_step(h, 0.0, unblended_switches);
  EXPECT_GT(unblended, blended);
  std::printf("force step at a switch: %.3f of the force blended over 5 ms, %.3f without\n", blended, unblended);
}

}  // namespace
}  // namespace tactus::lod
