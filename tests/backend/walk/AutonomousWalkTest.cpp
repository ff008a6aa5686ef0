// The headless autonomous walk across the simulated obstacle course, by the
// walk executive over the in-process link: 25 steps
// on seeds 1-5 with the default noise, scored against the simulator's truth.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "walk/AutonomousWalk.h"

namespace ambler::walk {
namespace {

WalkSetup config() { return readInstalledWalkSetup(); }

class WalkOnSeed : public testing::TestWithParam<int> {};

TEST_P(WalkOnSeed, TwentyFiveStepsStableWithoutCollisions) {
  WalkOptions o;
  o.course.seed = std::uint64_t(GetParam());
  o.steps = 25;
  const WalkResult r = runWalk(config(), o);
  EXPECT_EQ(r.steps, 25) << r.stopped;
  EXPECT_EQ(r.csp_violations, 0);
  EXPECT_EQ(r.leg_collisions, 0);
  EXPECT_GT(r.distance_m, 5.0);
  EXPECT_GT(r.min_stability_margin_m, 0.0);
  // Any single supporting leg may fail at any moment: the centre of gravity
  // stays inside the support polygon of the others.
  EXPECT_GT(r.min_margin_one_foot_lost_m, 0.0);
  EXPECT_TRUE(std::isfinite(r.min_margin_one_foot_lost_m));
  // The rover reports dead reckoning, which drifts (cmu-1990: typically
  // 1-2 cm per move): some error, bounded by a few cm per step.
  ASSERT_EQ(r.log.size(), 25u);
  EXPECT_GT(r.pose_error_max_m, 0.0);
  EXPECT_LE(r.pose_error_max_m, 0.02 * 25);
  EXPECT_EQ(r.pose_error_final_m, r.log.back().pose_error_m);
  // Along the track and across it: the same error, split.
  for (const auto& step : r.log) {
    EXPECT_NEAR(std::hypot(step.pose_error_along_m, step.pose_error_across_m), step.pose_error_m,
                1e-12);
    EXPECT_NEAR(std::hypot(step.dead_reckoning_error_along_m, step.dead_reckoning_error_across_m),
                step.dead_reckoning_error_m, 1e-12);
  }
}

INSTANTIATE_TEST_SUITE_P(Seeds, WalkOnSeed, testing::Values(1, 2, 3, 4, 5));

TEST(Walk, SequentialModeWalksToo) {
  WalkOptions o;
  o.course.seed = 3;
  o.steps = 10;
  o.concurrent = false;
  const WalkResult r = runWalk(config(), o);
  EXPECT_EQ(r.steps, 10) << r.stopped;
  EXPECT_EQ(r.replans, 0);
  EXPECT_EQ(r.csp_violations, 0);
  // Every step's moves and scan are accounted for: 10 scans of 0.5 s at
  // least, and ground work was timed.
  EXPECT_GT(r.modelled_execution_s, 10 * 0.5);
  EXPECT_GT(r.ground_work.total_s(), 0.0);
  // Scaled to the Ambler's ratio, execution takes 0.75 of the ground's work.
  EXPECT_NEAR(timeScaleOfTheReport(r) * r.modelled_execution_s, 0.75 * r.ground_work.total_s(),
              1e-12);
  EXPECT_EQ(timeScaleOfTheReport(WalkResult{}), 0.0);
}

// cmu-1990 'Real-time control': dead reckoning 'can often detect when
// individual feet have slipped'. Feet slipping one at a time leave the
// walk stable and the rover's own pose within a few centimetres (ground
// creep, which no leg can sense, is left out here).
TEST(Walk, SingleFootSlipsAreCaughtByDeadReckoning) {
  WalkOptions o;
  o.course.seed = 2;
  o.steps = 12;
  o.register_scans = false;
  WalkSetup c = config();
  c.rover.noise.slip_probability = 0.1;
  c.rover.noise.slip_m = 0.08;
  c.rover.noise.ground_creep_m = c.rover.noise.ground_creep_rad = 0.0;
  const WalkResult r = runWalk(c, o);
  EXPECT_EQ(r.steps, 12) << r.stopped;
  ASSERT_GT(r.slips, 3);
  EXPECT_LT(r.dead_reckoning_error_max_m, 0.03);
  EXPECT_EQ(r.pose_error_max_m, r.dead_reckoning_error_max_m) << "nothing corrects it";
  for (const auto& step : r.log) {
    EXPECT_EQ(step.heading_error_rad, step.dead_reckoning_heading_error_rad);
    EXPECT_EQ(step.pose_error_along_m, step.dead_reckoning_error_along_m);
    EXPECT_EQ(step.pose_error_across_m, step.dead_reckoning_error_across_m);
    EXPECT_LT(std::abs(step.dead_reckoning_heading_error_rad), 0.003);  // the heading too
  }
  EXPECT_EQ(r.scans_registered, 0);
  EXPECT_EQ(r.csp_violations, 0);
}

// A foot that meets a rock under its sole's rim leaves the height it met in
// the map, and the next plan chooses another foothold. On rock field 6
// (20 %, a tuning seed) three such contacts in a row, at footholds within
// 0.3 m of each other, come before the second step: each taught the map,
// and the fourth plan finds ground the foot reaches.
TEST(Walk, EarlyContactsAtNewFootholdsDoNotStopTheWalk) {
  const WalkResult r = runWalk(config(), onCourse("rocks20", 6, 5));
  EXPECT_EQ(r.steps, 5) << r.stopped;
  EXPECT_TRUE(std::ranges::any_of(r.log, [](const WalkStep& s) {
    return s.event.find("(early contact), replanned") != std::string::npos;
  }));
  EXPECT_EQ(r.csp_violations, 0);
  EXPECT_EQ(r.leg_collisions, 0);
}

}  // namespace
}  // namespace ambler::walk
