// The ground's pose correction against simulator truth: a scan whose pose
// is off by a known shift and turn is put back; level ground, which cannot
// hold a scan in place, is refused; a rover whose dead reckoning jumps
// 0.3 m is put back where it is.
#include "executive/ScanMatching.h"

#include <gtest/gtest.h>

#include <chrono>
#include <mutex>

#include "InstalledConfig.h"
#include "executive/WalkExecutive.h"
#include "rover/InProcessLink.h"
#include "sim/HeightfieldTerrain.h"
#include "sim/ProceduralTerrain.h"
#include "sim/RayCaster.h"
#include "sim/RoverWorld.h"
#include "sim/ScannerSim.h"
#include "sim/TerrainFamilies.h"
#include "terrain/Merge.h"

namespace ambler::executive {
namespace {

using namespace std::chrono_literals;

sim::ExecutionNoise exact() {
  sim::ExecutionNoise n;
  n.encoder_rotation_rad = n.encoder_extension_m = n.encoder_vertical_m = 0;
  n.placement_m = n.body_m = n.body_rad = n.slip_probability = 0;
  n.ground_creep_m = n.ground_creep_rad = 0;
  return n;
}

// Rotation by `yaw` about the vertical through `centre`, then `shift`.
Eigen::Isometry3d turnAbout(const Eigen::Vector3d& centre, double yaw,
                            const Eigen::Vector3d& shift) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  t.translation() = centre - t.linear() * centre + shift;
  return t;
}

double yawOf(const Eigen::Matrix3d& r) { return std::atan2(r(1, 0), r(0, 0)); }

class ScanMatchingTest : public ::testing::Test {
 protected:
  static constexpr Box2 kArea{-10, -8, 10, 30};
  ScanMatchingTest()
      : world_(sim::longTraverse(11), cfg().model, cfg().gait, exact(), cfg().scanner, kArea),
        map_(GridSpec::covering(kArea, 0.1)) {
    terrain::mergeScan(map_, world_.scan(1));
    (void)world_.rover().executeBody({Eigen::Vector2d(0.0, 0.5), 0.0, 0.0});
  }
  static const rover::SimulatedRoverConfig& cfg() { return testing_config::simulator(); }

  sim::RoverWorld world_;
  terrain::ElevationMap map_;
};

TEST_F(ScanMatchingTest, PutsBackAScanOffByAKnownShiftAndTurn) {
  const sensor::RangeImage truth = world_.scan(2);
  sensor::RangeImage off = truth;
  const Eigen::Vector3d scanner = truth.sensor_to_world.translation();
  off.sensor_to_world = turnAbout(scanner, 0.005, {0.10, -0.05, 0.02}) * truth.sensor_to_world;
  const ScanMatch m = matchScanToMap(off, map_, {});
  ASSERT_TRUE(m.accepted) << m.refused;
  const Eigen::Isometry3d placed = m.correction.transform() * off.sensor_to_world;
  EXPECT_LT((placed.translation() - scanner).head<2>().norm(), 0.01);
  EXPECT_NEAR(placed.translation().z(), scanner.z(), 0.005);
  EXPECT_NEAR(yawOf(placed.linear() * truth.sensor_to_world.linear().transpose()), 0.0, 0.001);
  EXPECT_GT(m.points, 5000);
  EXPECT_LT(m.sigma_xy_m, 0.01);
}

TEST_F(ScanMatchingTest, LevelGroundCannotHoldAScanAndIsRefused) {
  terrain::ElevationMap level(map_.grid());
  for (int r = 0; r < level.grid().rows; ++r)
    for (int c = 0; c < level.grid().cols; ++c) level.setKnown(r, c, 0.0, 0.01);
  sensor::RangeImage scan = world_.scan(2);
  const ScanMatch m = matchScanToMap(scan, level, {});
  EXPECT_FALSE(m.accepted);
  EXPECT_NE(m.refused.find("does not hold the scan"), std::string::npos) << m.refused;
  EXPECT_EQ(m.correction.shift, Eigen::Vector2d::Zero()) << "a refused match leaves the prior";
}

// On a rock field the map's 10 cm cells round the small rocks off, while a
// scan samples their faces sharply, and only the faces turned towards it.
// Scans taken where the rover truly stands, 0.5 m apart along +y, each
// matched against the map of the ones before: while the scan's own steep
// returns counted, the match moved them 1.7 cm forward on average; while
// their neighbours along the line of sight (the flanks) counted, 6.8 mm.
TEST(ScanMatching, RocksDoNotPullAScanAlongTheLineOfSight) {
  const sim::ProceduralTerrain field(sim::makeRockField({.seed = 5, .abundance = 0.2}));
  const GridSpec area = GridSpec::covering({-10, -2, 10, 24}, 0.02);
  const sim::HeightfieldTerrain heights(sim::sampleHeights(field, area), area);
  const sim::RayCaster caster(heights, {.cell_size = 0.25, .step = 0.1, .tolerance = 1e-3});
  const sim::ScannerModel scanner = testing_config::simulator().scanner;
  terrain::ElevationMap map(GridSpec::covering({-8, -2, 8, 22}, 0.1));
  double along = 0.0;
  int matched = 0;
  for (int i = 0; i < 24; ++i) {
    const Eigen::Vector3d ground(0.0, 0.5 * i, field.height(0.0, 0.5 * i));
    const auto scan = sim::simulateScan(caster, scanner, scanner.mountPose(ground), 100 + i);
    if (i >= 3) {
      const ScanMatch m = matchScanToMap(scan, map, {});
      if (m.accepted) along += m.offset.y(), ++matched;
    }
    terrain::mergeScan(map, scan);
  }
  ASSERT_GE(matched, 6);
  EXPECT_LT(std::abs(along / matched), 0.003) << "mean shift along +y of " << matched << " scans";
}

TEST_F(ScanMatchingTest, OptionsOutOfRangeAreNamed) {
  ScanMatchOptions o;
  o.max_slope = -1;
  EXPECT_THROW(
      {
        try {
          validate(o);
        } catch (const std::invalid_argument& e) {
          EXPECT_NE(std::string(e.what()).find("max_slope"), std::string::npos);
          throw;
        }
      },
      std::invalid_argument);
}

// The rover's dead reckoning jumps by `offset` once `slid` is set, as
// after a slide of the whole stance that no leg felt: its body pose and
// the pose its scans are tagged with.
class SlidingDeadReckoning : public link::Link {
 public:
  SlidingDeadReckoning(link::Link& inner, Eigen::Vector2d offset)
      : inner_(inner), offset_(std::move(offset)) {}
  void send(const link::Command& command) override { inner_.send(command); }
  std::vector<link::Telemetry> receive(std::chrono::milliseconds timeout) override {
    auto out = inner_.receive(timeout);
    if (!slid) return out;
    for (auto& m : out) {
      if (auto* b = std::get_if<link::BodyState>(&m.body)) {
        b->x_m += offset_.x(), b->y_m += offset_.y();
      } else if (auto* r = std::get_if<sensor::RangeImage>(&m.body)) {
        r->sensor_to_world.pretranslate(Eigen::Vector3d(offset_.x(), offset_.y(), 0.0));
      }
    }
    return out;
  }
  std::string describe() const override { return "sliding " + inner_.describe(); }
  bool slid = false;

 private:
  link::Link& inner_;
  Eigen::Vector2d offset_;
};

// A step planned under one correction is moved to the next by the second
// after the first undone: applying a correction and then its inverse leaves
// a stance where it was.
TEST(PoseCorrection, ItsInverseUndoesItAndTwoComposeAsOne) {
  const PoseCorrection c{{0.3, -0.2}, 0.05, 0.02};
  gait::Stance s;
  s.body.xy = {1.0, 2.0};
  s.body.heading_rad = 0.4;
  s.body.link_z = 1.5;
  for (int i = 0; i < gait::kLegCount; ++i) s.feet[std::size_t(i)] = {i * 0.5, 3.0 - i, 0.1 * i};
  const gait::Stance back = c.inverse().apply(c.apply(s));
  EXPECT_NEAR((back.body.xy - s.body.xy).norm(), 0.0, 1e-12);
  EXPECT_NEAR(back.body.heading_rad, s.body.heading_rad, 1e-12);
  EXPECT_NEAR(back.body.link_z, s.body.link_z, 1e-12);
  for (int i = 0; i < gait::kLegCount; ++i)
    EXPECT_NEAR((back.feet[std::size_t(i)] - s.feet[std::size_t(i)]).norm(), 0.0, 1e-12) << i;
  const Eigen::Isometry3d identity = c.transform() * c.inverse().transform();
  EXPECT_TRUE(identity.isApprox(Eigen::Isometry3d::Identity(), 1e-12));

  // Composed, two corrections act as one after the other.
  const PoseCorrection d{{-0.1, 0.4}, -0.02, -0.01};
  const gait::Stance twice = (d * c).apply(s);
  const gait::Stance each = d.apply(c.apply(s));
  EXPECT_NEAR((twice.body.xy - each.body.xy).norm(), 0.0, 1e-12);
  EXPECT_NEAR(twice.body.heading_rad, each.body.heading_rad, 1e-12);
  EXPECT_NEAR(twice.body.link_z, each.body.link_z, 1e-12);
  EXPECT_TRUE((d * c).transform().isApprox(d.transform() * c.transform(), 1e-12));
}

TEST(PoseCorrector, ADeadReckoningJumpOf30CmIsPulledBackWithin3Cm) {
  const link::OperatorKey key{"test", std::vector<std::uint8_t>(32, 7)};
  rover::SimulatedRoverOptions rover_options;
  rover_options.course = sim::longTraverse(11);
  rover_options.operators = {key};
  rover_options.scanned_area = {-10, -8, 10, 40};
  std::mutex mutex;
  gait::BodyPose truth;
  rover::InProcessLink rover(testing_config::simulator(), rover_options, 1000ms,
                             [&](const link::Command&, const rover::SimulatedRover& r) {
                               const std::lock_guard lock(mutex);
                               truth = r.world().rover().truth().body;
                             });
  SlidingDeadReckoning sliding(rover, {0.3, 0.0});
  link::CommandSigner signer(key);
  ApprovalGate gate;
  gate.setMode(ApprovalMode::kAutoApprove);
  ExecutiveOptions options;
  options.steps = 16;
  options.map_extent = rover_options.scanned_area;
  WalkExecutive walk(sliding, signer, gate, testing_config::ground(), options);
  double now = 0.0;
  walk.start(now);
  for (int i = 0; i < 20000 && walk.phase() != Phase::kDone; ++i) {
    sliding.slid = walk.stepsDone() >= 6;
    walk.poll(now += 0.05, 10ms);
  }
  ASSERT_EQ(walk.phase(), Phase::kDone) << (walk.events().empty() ? "" : walk.events().back().what);
  const std::lock_guard lock(mutex);
  const auto reported = walk.report().stance(testing_config::ground().model);
  ASSERT_TRUE(reported);
  EXPECT_GT((reported->body.xy - truth.xy).norm(), 0.25) << "the rover's own pose is still off";
  EXPECT_LT((walk.reported()->body.xy - truth.xy).norm(), 0.03);
  int relocated = 0;
  for (const auto& m : walk.scanMatches()) relocated += m.relocated;
  EXPECT_EQ(relocated, 1);
}

}  // namespace
}  // namespace ambler::executive
