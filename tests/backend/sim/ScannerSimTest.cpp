#include "sim/ScannerSim.h"

#include <gtest/gtest.h>

#include "backend/sim/FlatGround.h"
#include "core/Angles.h"
#include "core/Resources.h"
#include "sim/ProceduralTerrain.h"

namespace ambler::sim {
namespace {

ScannerModel model(int rows, int cols, double k) {
  ScannerModel m;
  m.geometry = sensor::ScanGeometry::symmetric(rows, cols, 30 * kDeg, 60 * kDeg);
  m.range_sigma_k = k;
  m.max_range = 40;
  m.mount_height = 5;
  m.tilt = 30 * kDeg;
  return m;
}

TEST(ScannerSim, FlatPlaneGivesTheAnalyticRange) {
  const auto ground = flatGround();
  const RayCaster caster(ground);
  const auto m = model(64, 96, 0.0);
  const auto scan = simulateScan(caster, m, m.mountPose({0, 0, 0}), 1);
  int checked = 0;
  for (int r = 0; r < scan.rows(); ++r)
    for (int c = 0; c < scan.cols(); ++c) {
      // Depression of this pixel's ray is tilt - phi; the plane is H below.
      const double depression = m.tilt - m.geometry.phi(r);
      const double expected =
          m.mount_height / (std::cos(m.geometry.theta(c)) * std::sin(depression));
      ASSERT_TRUE(scan.hasReturn(r, c)) << r << "," << c;
      ASSERT_NEAR(scan.at(r, c), expected, 1e-3) << r << "," << c;
      ++checked;
    }
  EXPECT_EQ(checked, 64 * 96);
}

TEST(ScannerSim, RaysAboveTheHorizonOrBeyondRangeReturnNothing) {
  const auto ground = flatGround();
  const RayCaster caster(ground);
  auto m = model(32, 32, 0.0);
  m.tilt = 5 * kDeg;  // the upper half of the image looks above the horizon
  m.max_range = 30;
  const auto scan = simulateScan(caster, m, m.mountPose({0, 0, 0}), 1);
  for (int r = 0; r < scan.rows(); ++r) {
    const double depression = m.tilt - m.geometry.phi(r);
    const double range_at_centre = depression > 0 ? m.mount_height / std::sin(depression) : 1e9;
    if (range_at_centre > 31) {
      EXPECT_FALSE(scan.hasReturn(r, 16)) << r;
    }
    if (range_at_centre < 29) {
      EXPECT_TRUE(scan.hasReturn(r, 16)) << r;
    }
  }
}

TEST(ScannerSim, NoiseStdMatchesKRhoSquaredWithin5Percent) {
  const auto ground = flatGround();
  const RayCaster caster(ground);
  const double k = 1e-3;
  const auto noisy_model = model(320, 320, k);
  const auto pose = noisy_model.mountPose({0, 0, 0});
  const auto noisy = simulateScan(caster, noisy_model, pose, 99);
  const auto exact = simulateScan(caster, model(320, 320, 0.0), pose, 99);
  double sum = 0, sum_sq = 0;
  int n = 0;
  for (std::size_t i = 0; i < exact.range.size(); ++i) {
    const double truth = exact.range[i];
    const double z = (noisy.range[i] - truth) / sensor::rangeSigma(truth, k);
    sum += z;
    sum_sq += z * z;
    ++n;
  }
  ASSERT_GE(n, 100000);
  const double mean = sum / n, std_dev = std::sqrt(sum_sq / n - mean * mean);
  EXPECT_NEAR(mean, 0.0, 0.02);
  EXPECT_NEAR(std_dev, 1.0, 0.05);
}

TEST(ScannerSim, SameSeedSameNoise) {
  const auto ground = flatGround();
  const RayCaster caster(ground);
  const auto m = model(16, 16, 1e-3);
  const auto pose = m.mountPose({0, 0, 0});
  EXPECT_EQ(simulateScan(caster, m, pose, 5).range, simulateScan(caster, m, pose, 5).range);
  EXPECT_NE(simulateScan(caster, m, pose, 5).range, simulateScan(caster, m, pose, 6).range);
}

// A 1 m tall box whose faces are at y = 9.5 and 10.5, seen from 5 m up at
// the origin: its shadow on the ground ends where the line from the sensor
// over the box's far top edge meets the ground, y = 10.5 * 5 / (5 - 1).
TEST(ScannerSim, BoxCastsAShadowOfTheAnalyticLength) {
  const auto ground = flatGround({BoxObstacle{{0.0, 10.0, 0.0, 0.5, 0.5}, 1.0}});
  const RayCaster caster(ground);
  const auto m = model(64, 64, 0.0);
  const auto pose = m.mountPose({0, 0, 0});
  const double res = 0.01;
  const GridSpec column{-0.005, 8.0, res, int(7.0 / res), 1};  // cells along x = 0
  const auto truth = computeVisibility(caster, m, pose, column);

  const double shadow_end = 10.5 * 5.0 / 4.0;
  double shadow_length = 0;
  for (int r = 0; r < column.rows; ++r) {
    const double y = column.cellCenter(r, 0).y();
    const auto state = Visibility(truth.state(r, 0));
    if (y < 10.5 - res || y > shadow_end + res) {
      EXPECT_EQ(state, Visibility::kVisible) << y;
    }
    if (y > 10.5 + res && y < shadow_end - res) {
      EXPECT_EQ(state, Visibility::kOccluded) << y;
    }
    if (state == Visibility::kOccluded) shadow_length += res;
    const double expected_z = std::abs(y - 10.0) < 0.5 ? 1.0 : 0.0;
    if (std::abs(std::abs(y - 10.0) - 0.5) > res) {
      EXPECT_EQ(truth.height(r, 0), expected_z) << y;
    }
  }
  EXPECT_NEAR(shadow_length, shadow_end - 10.5, 2 * res);
}

TEST(ScannerSim, CellsOutsideTheFieldOfViewAreUnknown) {
  const auto ground = flatGround();
  const RayCaster caster(ground);
  const auto m = model(32, 32, 0.0);
  const GridSpec grid{-0.05, -3.0, 0.1, 400, 1};  // y from -3 to 37 m along x = 0
  const auto truth = computeVisibility(caster, m, m.mountPose({0, 0, 0}), grid);
  // Visible band: depression 15..45 degrees, i.e. y from 5 / tan 45 to 5 / tan 15.
  for (int r = 0; r < grid.rows; ++r) {
    const double y = grid.cellCenter(r, 0).y();
    const auto state = Visibility(truth.state(r, 0));
    if (y < 4.9 || y > 18.8) {
      EXPECT_EQ(state, Visibility::kOutsideView) << y;
    }
    if (y > 5.1 && y < 18.5) {
      EXPECT_EQ(state, Visibility::kVisible) << y;
    }
  }
}

TEST(RayCaster, HitsVerticalFacesAndTopsExactly) {
  const auto ground = flatGround({BoxObstacle{{0.0, 10.0, 0.0, 0.5, 0.5}, 1.0}});
  const RayCaster caster(ground);
  EXPECT_NEAR(*caster.cast({0, 0, 0.5}, {0, 1, 0}, 50), 9.5, 1e-9);
  EXPECT_NEAR(*caster.cast({0.2, 10.2, 5}, {0, 0, -1}, 50), 4.0, 1e-9);
  EXPECT_FALSE(caster.cast({0, 0, 5}, {0, 0, 1}, 50).has_value());
  EXPECT_FALSE(caster.cast({0, 0, -1}, {0, 1, 0}, 50).has_value());  // starts underground
}

TEST(ScannerModel, DefaultConfigurationLoads) {
  const auto m = readScannerModel(findResource("config/scanner.json"));
  EXPECT_EQ(m.geometry.rows, 256);
  EXPECT_EQ(m.geometry.cols, 256);
  EXPECT_GT(m.range_sigma_k, 0.0);
  EXPECT_NEAR(m.geometry.phi(-0.5) - m.geometry.phi(255.5), 30 * kDeg, 1e-12);
}

}  // namespace
}  // namespace ambler::sim
