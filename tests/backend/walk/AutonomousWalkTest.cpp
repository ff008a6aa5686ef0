// The headless autonomous walk across the simulated obstacle course
// (issue 5's acceptance): 25 steps on seeds 1-5 with the default noise.
#include <gtest/gtest.h>

#include "walk/AutonomousWalk.h"

namespace ambler::walk {
namespace {

WalkConfig config() { return readDefaultWalkConfig(); }

class WalkOnSeed : public testing::TestWithParam<int> {};

TEST_P(WalkOnSeed, TwentyFiveStepsStableWithoutCollisions) {
  WalkOptions o;
  o.seed = std::uint64_t(GetParam());
  o.steps = 25;
  const WalkResult r = runWalk(config(), o);
  EXPECT_EQ(r.steps, 25) << r.stopped;
  EXPECT_EQ(r.csp_violations, 0);
  EXPECT_EQ(r.leg_collisions, 0);
  EXPECT_GT(r.distance_m, 5.0);
  EXPECT_GT(r.min_stability_margin_m, 0.0);
  EXPECT_LE(r.dead_reckoning_error_m, 0.02);  // cmu-1990: typically 1-2 cm
  // Any single supporting leg may fail at any moment: the centre of gravity
  // stays inside the support polygon of the others.
  ASSERT_FALSE(r.trace.empty());
  for (const auto& s : r.trace)
    for (std::size_t lost = 0; lost < s.feet.size(); ++lost) {
      std::vector<Eigen::Vector2d> rest = s.feet;
      rest.erase(rest.begin() + long(lost));
      ASSERT_GT(gait::stabilityMargin(gait::supportPolygon(rest), s.centre_of_gravity), 0.0);
    }
}

INSTANTIATE_TEST_SUITE_P(Seeds, WalkOnSeed, testing::Values(1, 2, 3, 4, 5));

TEST(Walk, SequentialModeWalksToo) {
  WalkOptions o;
  o.seed = 3;
  o.steps = 10;
  o.concurrent = false;
  const WalkResult r = runWalk(config(), o);
  EXPECT_EQ(r.steps, 10) << r.stopped;
  EXPECT_EQ(r.replans, 0);
  EXPECT_EQ(r.csp_violations, 0);
  // Every step's moves and scan are accounted for: 10 scans of 0.5 s at
  // least, and ground work was timed.
  EXPECT_GT(r.modelled_execution_s, 10 * 0.5);
  EXPECT_GT(r.ground_busy_s, 0.0);
  // Scaled to the Ambler's ratio, execution takes 0.75 of the ground's work.
  EXPECT_NEAR(timeScaleOfTheReport(r) * r.modelled_execution_s, 0.75 * r.ground_busy_s, 1e-12);
  EXPECT_EQ(timeScaleOfTheReport(WalkResult{}), 0.0);
}

TEST(Walk, SlipsAreFoundByDeadReckoning) {
  WalkConfig c = config();
  c.noise.slip_probability = 0.1;
  c.noise.slip_m = 0.08;
  WalkOptions o;
  o.seed = 2;
  o.steps = 12;
  const WalkResult r = runWalk(c, o);
  ASSERT_GT(r.slips, 3);
  EXPECT_GE(r.slips_detected, r.slips - 1);  // a slip along the fit can hide
  EXPECT_EQ(r.csp_violations, 0);
}

}  // namespace
}  // namespace ambler::walk
