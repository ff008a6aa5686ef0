// Global localization of a simulated scan in a coarse model of the course,
// without a prior on position or heading (bakambu-csa §2).
#include "mapping/Localization.h"

#include <gtest/gtest.h>

#include <cmath>

#include "backend/mapping/SimulatedView.h"
#include "core/Resources.h"
#include "sim/CourseScene.h"

namespace ambler::mapping {
namespace {

using test::View;
using test::viewFrom;

// The course as a model from orbital altimetry at 1 m over `region`.
Cloud coarseModel(std::uint64_t seed, const Box2& region) {
  const sim::CourseScene scene(seed, sim::readScannerModel(findResource("config/scanner.json")));
  return sim::orbitalModel(scene.terrain(), GridSpec::covering(region, 1.0));
}

double angleDeg(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle() * 180 / M_PI;
}

// A scan taken 3.6 m from the model's centre, facing south-west: found
// within 0.5 m and 2 degrees (the bound), anywhere in a 60 m model.
TEST(Localization, FindsAScanAnywhereInTheCoarseModel) {
  const View a = viewFrom(4, {2.0, -3.0}, 2.3);
  const auto r =
      localize(a.points, withoutYaw(a.pose.linear()), coarseModel(4, {-30, -30, 30, 30}));
  ASSERT_TRUE(r.has_value());
  EXPECT_LT((r->transform.translation() - a.pose.translation()).norm(), 0.5);
  EXPECT_LT(angleDeg(r->transform.linear(), a.pose.linear()), 2.0);
}

// A model smaller than the scan's footprint cannot hold it: not found,
// rather than a guess.
TEST(Localization, AModelSmallerThanTheScanGivesNoPlacement) {
  const View a = viewFrom(4, {0, 0}, 0);
  const auto r = localize(a.points, withoutYaw(a.pose.linear()), coarseModel(4, {-3, 5, 3, 11}));
  EXPECT_FALSE(r.has_value());
}

TEST(Localization, BadInputIsRefusedWithTheProblemNamed) {
  const View a = viewFrom(4, {0, 0}, 0);
  const auto model = coarseModel(4, {-10, -10, 10, 10});
  GlobalOptions bad;
  bad.yaw_step_deg = 0;
  EXPECT_THROW(localize(a.points, Eigen::Matrix3d::Identity(), model, bad), std::invalid_argument);
  const Cloud few{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  try {
    localize(few, Eigen::Matrix3d::Identity(), model);
    ADD_FAILURE() << "a three-point scan was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("cells; at least 10"), std::string::npos) << e.what();
  }
  Cloud nan_model = model;
  nan_model[3].z() = NAN;
  EXPECT_THROW(localize(a.points, Eigen::Matrix3d::Identity(), nan_model), std::invalid_argument);
}

}  // namespace
}  // namespace ambler::mapping
