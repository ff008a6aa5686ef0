// The simulated rover executing leg and body moves (cmu-1990 'Real-time
// control'): synchronised joints, contact stop, trapezoidal body moves,
// slip and collisions.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "gait/GaitPlanner.h"
#include "io/FormatError.h"
#include "sim/RoverSim.h"

namespace ambler::sim {
namespace {

// Flat ground at z = 0 with an optional block.
class BlockGround : public Terrain {
 public:
  explicit BlockGround(Box2 block = {}, double height = 0.0) : block_(block), height_(height) {}
  double height(double x, double y) const override { return block_.contains(x, y) ? height_ : 0.0; }
  double maxHeightIn(const Box2&) const override { return height_; }
  Box2 extent() const override { return {-50, -50, 50, 50}; }

 private:
  Box2 block_;
  double height_;
};

ExecutionNoise noNoise() {
  ExecutionNoise n;
  n.encoder_rotation_rad = n.encoder_extension_m = n.encoder_vertical_m = 0;
  n.placement_m = n.body_m = n.body_rad = n.slip_probability = 0;
  n.ground_creep_m = n.ground_creep_rad = 0;
  return n;
}

gait::Stance start(const Terrain& t, const gait::RoverModel& m) {
  return settleOnTerrain(gait::nominalStance({{0, 0}, 0.0, 2.4}, m, gait::GaitOptions{}), t, m);
}

// A terrain model's no-data under a foot of the start: refused, naming the
// foot, rather than a stance at NaN.
TEST(RoverSim, RefusesToStartWithAFootOverNoData) {
  const gait::RoverModel m;
  const BlockGround hole_under_foot_3({1.5, -1.5, 3.0, 0.0}, NAN);
  try {
    (void)start(hole_under_foot_3, m);
    ADD_FAILURE() << "settled over no-data";
  } catch (const NoGroundError& e) {
    EXPECT_NE(std::string(e.what()).find("foot 3 at (2.25, -0.75) m"), std::string::npos)
        << e.what();
  }
  const BlockGround hole_between_feet({-1.0, -1.0, 1.0, 1.0}, NAN);
  const gait::Stance s = start(hole_between_feet, m);
  for (const auto& foot : s.feet) EXPECT_EQ(foot.z(), 0.0);
}

TEST(RoverSim, JointsArriveTogetherAndTheFootStopsOnContact) {
  const BlockGround ground;
  const gait::RoverModel m;
  RoverSim rover(ground, m, noNoise(), start(ground, m));
  const gait::LegJoints q0 = rover.truth().joints(m, 5);
  // Lift 0.5 m; swing 0.3 rad while extending 0.1 m; lower towards 0.2 m
  // below the ground.
  const gait::LegJoints up{q0.rotation_rad, q0.extension_m, q0.vertical_m - 0.5};
  const gait::LegJoints over{q0.rotation_rad + 0.3, q0.extension_m - 0.1, up.vertical_m};
  const gait::LegJoints down{over.rotation_rad, over.extension_m, q0.vertical_m + 0.2};
  const MoveReport r = rover.executeLeg({5, {up, over, down}});
  EXPECT_TRUE(r.completed);
  EXPECT_EQ(r.event, "touch-down");
  EXPECT_EQ(r.collisions, 0);
  // 0.5 m up, then max(0.3 rad, 0.1 m) at 0.15 per second, then 0.5 m down
  // to the ground where the contact stops it.
  const double expected =
      0.5 / m.vertical_speed_m_s + 0.3 / m.rotation_speed_rad_s + 0.5 / m.vertical_speed_m_s;
  EXPECT_NEAR(r.duration_s, expected, 0.03 * expected);
  const gait::LegJoints landed = rover.truth().joints(m, 5);
  EXPECT_NEAR(landed.rotation_rad, over.rotation_rad, 1e-9);
  EXPECT_NEAR(rover.truth().feet[5].z(), 0.0, 1e-9);
  EXPECT_TRUE(rover.legStates()[5].contact);
}

TEST(RoverSim, ASwingThroughABlockIsACollision) {
  const gait::RoverModel m;
  const BlockGround flat;
  const gait::Stance s = start(flat, m);
  const Eigen::Vector3d foot = s.feet[5];
  const BlockGround ground({foot.x() + 0.3, foot.y() - 1.0, foot.x() + 0.6, foot.y() + 1.0}, 1.0);
  RoverSim rover(ground, m, noNoise(), s);
  const gait::LegJoints q0 = s.joints(m, 5);
  const gait::LegJoints up{q0.rotation_rad, q0.extension_m, q0.vertical_m - 0.5};  // 0.5 m lift
  const gait::LegJoints out{q0.rotation_rad, q0.extension_m + 0.8, up.vertical_m};
  const gait::LegJoints down{out.rotation_rad, out.extension_m, q0.vertical_m};
  const MoveReport r = rover.executeLeg({5, {up, out, down}});
  EXPECT_FALSE(r.completed);
  EXPECT_EQ(r.event, "unexpected contact");
  EXPECT_EQ(r.collisions, 1);
}

TEST(RoverSim, BodyMovesFollowATrapezoidalProfile) {
  const BlockGround ground;
  const gait::RoverModel m;
  RoverSim rover(ground, m, noNoise(), start(ground, m));
  const MoveReport r = rover.executeBody({{0.0, 0.3}, 0.0, 0.0});
  // v^2 / a = 0.111 m < 0.3 m: cruise, with v / a seconds lost to ramps.
  EXPECT_NEAR(r.duration_s, 0.3 / m.body_speed_m_s + m.body_speed_m_s / m.body_accel_m_s2, 1e-9);
  EXPECT_NEAR((rover.truth().body.xy - Eigen::Vector2d(0, 0.3)).norm(), 0.0, 1e-12);
  // The centre of gravity nears the CSP edge y = 0.5 + x / 3 of the nominal
  // stance: 0.2 m short of it along y at the end.
  EXPECT_NEAR(r.min_csp_margin_m, 0.2 / std::sqrt(10.0 / 9.0), 1e-9);
  EXPECT_EQ(rover.trace().size(), 15u);  // sampled every 2 cm
  // Short moves never reach cruise speed: 2 sqrt(d / a).
  EXPECT_NEAR(rover.executeBody({{0.0, 0.05}, 0.0, 0.0}).duration_s, 2 * std::sqrt(0.05 / 0.01),
              1e-9);
}

TEST(RoverSim, SlipsMoveFeetAndEncodersReportTheTruth) {
  const BlockGround ground;
  const gait::RoverModel m;
  ExecutionNoise n = noNoise();
  n.slip_probability = 1.0;
  n.slip_m = 0.05;
  const gait::Stance s = start(ground, m);
  RoverSim rover(ground, m, n, s);
  rover.executeBody({{0.0, 0.2}, 0.0, 0.0});
  EXPECT_EQ(rover.slips(), 6);
  for (int i = 0; i < gait::kLegCount; ++i) {
    EXPECT_NEAR((rover.truth().feet[std::size_t(i)] - s.feet[std::size_t(i)]).head<2>().norm(),
                0.05, 1e-9);
    const gait::LegJoints q = rover.legStates()[std::size_t(i)].joints;
    EXPECT_NEAR(
        (m.footInBody(i, q) - rover.truth().body.toBody(rover.truth().feet[std::size_t(i)])).norm(),
        0.0, 1e-9);
  }
}

// A wall 1.6 m high all round, with a pit under each foot just wider than
// the sole: every slip and creep would carry the sole onto the wall.
class PitsInAWall : public Terrain {
 public:
  PitsInAWall(const gait::Stance& s, double radius) : stance_(s), radius_(radius) {}
  double height(double x, double y) const override {
    for (const auto& f : stance_.feet)
      if ((f.head<2>() - Eigen::Vector2d(x, y)).norm() <= radius_) return 0.0;
    return 1.6;
  }
  double maxHeightIn(const Box2&) const override { return 1.6; }
  Box2 extent() const override { return {-50, -50, 50, 50}; }

 private:
  gait::Stance stance_;
  double radius_;
};

TEST(RoverSim, ASlidingSoleDoesNotClimbAWall) {
  const BlockGround flat;
  const gait::RoverModel m;
  const gait::Stance s = start(flat, m);
  const PitsInAWall pits(s, 0.5 * m.foot_diameter_m + 0.01);
  ExecutionNoise n = noNoise();
  n.slip_probability = 1.0;
  n.slip_m = 0.05;
  n.ground_creep_m = 0.1;
  RoverSim rover(pits, m, n, s);
  rover.executeBody({{0.0, 0.2}, 0.0, 0.0});
  EXPECT_EQ(rover.slips(), 0) << "no slip onto the wall";
  for (int i = 0; i < gait::kLegCount; ++i)
    EXPECT_NEAR((rover.truth().feet[std::size_t(i)] - s.feet[std::size_t(i)]).norm(), 0.0, 1e-9)
        << "foot " << i;
}

TEST(RoverSim, RefusesMalformedCommands) {
  const BlockGround ground;
  const gait::RoverModel m;
  RoverSim rover(ground, m, noNoise(), start(ground, m));
  EXPECT_THROW(rover.executeLeg({7, {gait::LegJoints{}}}), std::invalid_argument);
  EXPECT_THROW(rover.executeLeg({1, {}}), std::invalid_argument);
  EXPECT_THROW(rover.executeLeg({1, {{NAN, 1.0, 1.0}}}), std::invalid_argument);
  EXPECT_THROW(rover.executeBody({{INFINITY, 0.0}, 0.0, 0.0}), std::invalid_argument);
  EXPECT_TRUE(rover.trace().empty());  // nothing was executed
}

TEST(RoverSim, NoiseConfigurationIsChecked) {
  const auto path = std::filesystem::temp_directory_path() / "ambler_rover_noise_test.json";
  std::ofstream(path) << R"({"simulation": {"slip_probability": 2.0}})";
  try {
    readExecutionNoise(path);
    FAIL() << "accepted a probability of 2";
  } catch (const io::FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("slip_probability"), std::string::npos) << e.what();
  }
  std::ofstream(path) << R"({"simulation": {"slip_m": 0.02, "seed": 9}})";
  const ExecutionNoise n = readExecutionNoise(path);
  EXPECT_DOUBLE_EQ(n.slip_m, 0.02);
  EXPECT_EQ(n.seed, 9u);
  EXPECT_DOUBLE_EQ(n.placement_m, ExecutionNoise{}.placement_m);  // the default kept
  std::filesystem::remove(path);
}

// Static balance: the loads carry the weight with no moment about the
// centre of gravity; three feet around it share it as a lever would.
TEST(RoverSim, FootLoadsCarryTheWeightWithNoMoment) {
  const gait::RoverModel m;
  const BlockGround flat;
  gait::Stance s = start(flat, m);
  const double weight = m.mass_kg * 9.81;
  auto check = [&](const gait::Stance& stance) {
    const auto f = footLoads(stance, m);
    const Eigen::Vector2d cog = stance.centreOfGravity(m);
    double sum = 0;
    Eigen::Vector2d moment(0, 0);
    for (int i = 0; i < gait::kLegCount; ++i) {
      if (!stance.supporting[std::size_t(i)]) {
        EXPECT_EQ(f[std::size_t(i)], 0.0) << i;
      }
      sum += f[std::size_t(i)];
      moment += f[std::size_t(i)] * (stance.feet[std::size_t(i)].head<2>() - cog);
    }
    EXPECT_NEAR(sum, weight, 1e-6 * weight);
    EXPECT_NEAR(moment.norm(), 0.0, 1e-6 * weight);
    return f;
  };
  check(s);
  // Three feet: the unique split, by the centre of gravity's barycentric
  // coordinates in their triangle.
  const Eigen::Vector2d cog = s.centreOfGravity(m);
  s.feet[0].head<2>() = cog + Eigen::Vector2d(2.0, 0.0);
  s.feet[1].head<2>() = cog + Eigen::Vector2d(-1.0, 1.5);
  s.feet[2].head<2>() = cog + Eigen::Vector2d(-1.0, -1.5);
  for (int i = 3; i < gait::kLegCount; ++i) s.supporting[std::size_t(i)] = false;
  const auto f = check(s);
  EXPECT_NEAR(f[0], weight / 3, 1e-6 * weight);
  EXPECT_NEAR(f[1], weight / 3, 1e-6 * weight);
  // Both reach the link: what the simulated rover reports.
  RoverSim rover(flat, m, noNoise(), start(flat, m));
  EXPECT_NEAR(rover.legStates()[2].force_n, footLoads(rover.truth(), m)[2], 1e-9);
}

}  // namespace
}  // namespace ambler::sim
