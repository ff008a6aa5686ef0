// Kinematic dead reckoning (cmu-1990 'Real-time control'): the body pose
// from feet measured in the body frame and stored in the world.
#include <gtest/gtest.h>

#include <random>

#include "gait/DeadReckoning.h"
#include "gait/GaitPlanner.h"

namespace ambler::gait {
namespace {

struct Case {
  std::vector<int> legs{0, 1, 2, 3, 4, 5};
  std::vector<Eigen::Vector3d> body, world;
};

Case feetSeenFrom(const BodyPose& truth) {
  Case c;
  const double xs[] = {-2.25, -2.25, -2.25, 2.25, 2.25, 2.25}, ys[] = {-1, 0, 1, -0.5, 0.5, 1.5};
  for (int i = 0; i < 6; ++i) {
    const Eigen::Vector3d w(truth.xy.x() + 3 * xs[i], truth.xy.y() + ys[i] * 1.3, 0.1 * i);
    c.world.push_back(w);
    c.body.push_back(truth.toBody(w));
  }
  return c;
}

TEST(DeadReckoning, RecoversAnExactPose) {
  const BodyPose truth{{3.2, -1.5}, 0.4, 2.4};
  const Case c = feetSeenFrom(truth);
  const auto r = deadReckon(c.legs, c.body, c.world);
  ASSERT_TRUE(r.ok);
  EXPECT_NEAR((r.body.xy - truth.xy).norm(), 0.0, 1e-9);
  EXPECT_NEAR(r.body.heading_rad, truth.heading_rad, 1e-9);
  EXPECT_NEAR(r.body.link_z, truth.link_z, 1e-9);
  EXPECT_TRUE(r.slipped_legs.empty());
}

// Encoder noise of 2 mm per foot: the six-foot fit is better than any foot.
TEST(DeadReckoning, AveragesEncoderNoise) {
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.002);
  const BodyPose truth{{0, 10}, -0.2, 2.4};
  double worst = 0;
  for (int trial = 0; trial < 200; ++trial) {
    Case c = feetSeenFrom(truth);
    for (auto& b : c.body) b += Eigen::Vector3d(noise(rng), noise(rng), 0);
    const auto r = deadReckon(c.legs, c.body, c.world);
    worst = std::max(worst, (r.body.xy - truth.xy).norm());
  }
  EXPECT_LT(worst, 0.006);
}

TEST(DeadReckoning, DetectsASlippedFootAndLeavesItOut) {
  const BodyPose truth{{1, 2}, 0.1, 2.4};
  Case c = feetSeenFrom(truth);
  c.world[3] += Eigen::Vector3d(0.08, -0.05, 0);  // the stored position is no longer true
  const auto r = deadReckon(c.legs, c.body, c.world);
  ASSERT_TRUE(r.ok);
  ASSERT_EQ(r.slipped_legs, std::vector<int>{3});
  EXPECT_LT((r.body.xy - truth.xy).norm(), 1e-9);
}

// The rover's odometry with exact readings: a foot set down is stored where
// it is, and a body move (0.4 m forward, 0.05 rad left) is recovered
// exactly from the six feet.
TEST(KinematicOdometry, FollowsExactReadingsMoveByMove) {
  const RoverModel m;
  Stance truth = nominalStance({{1, 2}, 0.3, 2.4}, m, GaitOptions{});
  KinematicOdometry odometry(m, truth);
  truth.feet[2] += Eigen::Vector3d(0.0, 0.3, 0.05);  // leg 2 steps
  odometry.legMoved(2, truth.joints(m, 2));
  EXPECT_LT((odometry.estimate().feet[2] - truth.feet[2]).norm(), 1e-9);
  truth.body.xy += truth.body.rotation() * Eigen::Vector2d(0.0, 0.4);
  truth.body.heading_rad += 0.05;
  std::array<LegJoints, kLegCount> joints;
  for (int i = 0; i < kLegCount; ++i) joints[std::size_t(i)] = truth.joints(m, i);
  const auto r = odometry.bodyMoved(joints);
  EXPECT_TRUE(r.ok && r.slipped_legs.empty());
  EXPECT_LT((odometry.estimate().body.xy - truth.body.xy).norm(), 1e-9);
  EXPECT_NEAR(odometry.estimate().body.heading_rad, truth.body.heading_rad, 1e-9);
  EXPECT_NEAR(odometry.estimate().body.link_z, truth.body.link_z, 1e-9);
}

// A foot that slid 8 cm during a body move is left out of the fit and then
// stored where the encoders now put it, so the next move starts from it.
TEST(KinematicOdometry, StoresASlippedFootWhereItNowIs) {
  const RoverModel m;
  Stance truth = nominalStance({{0, 0}, 0.0, 2.4}, m, GaitOptions{});
  KinematicOdometry odometry(m, truth);
  truth.body.xy.y() += 0.3;
  truth.feet[4] += Eigen::Vector3d(0.08, 0.0, 0.0);
  std::array<LegJoints, kLegCount> joints;
  for (int i = 0; i < kLegCount; ++i) joints[std::size_t(i)] = truth.joints(m, i);
  const auto r = odometry.bodyMoved(joints);
  EXPECT_EQ(r.slipped_legs, std::vector<int>{4});
  EXPECT_LT((odometry.estimate().body.xy - truth.body.xy).norm(), 1e-9);
  EXPECT_LT((odometry.estimate().feet[4] - truth.feet[4]).norm(), 1e-9);
}

TEST(DeadReckoning, RefusesMismatchedInput) {
  EXPECT_THROW(deadReckon({0, 1}, {Eigen::Vector3d::Zero()}, {}), std::invalid_argument);
  EXPECT_FALSE(deadReckon({0, 1}, {{0, 0, 0}, {1, 0, 0}}, {{0, 0, 0}, {1, 0, 0}}).ok);
}

}  // namespace
}  // namespace ambler::gait
