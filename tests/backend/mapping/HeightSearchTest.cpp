// The coarse stage of registration on an analytic height field.
#include "mapping/HeightSearch.h"

#include <gtest/gtest.h>

#include <cmath>

namespace ambler::mapping {
namespace {

double height(double x, double y) {
  return 0.3 * std::sin(0.9 * x + 0.4) * std::cos(0.7 * y) + 0.15 * std::sin(2.3 * x - 1.7 * y) +
         0.02 * x;
}

std::vector<Eigen::Vector3d> ground(double x0, double x1, double y0, double y1, double step) {
  std::vector<Eigen::Vector3d> out;
  for (double x = x0; x <= x1; x += step)
    for (double y = y0; y <= y1; y += step) out.emplace_back(x, y, height(x, y));
  return out;
}

// A patch of the ground moved by 0.3 m, 3 degrees about z and 2 degrees of
// tilt: the search finds the motion back to within a few centimetres and
// a tenth of a degree.
TEST(HeightSearch, FindsTheShiftTurnAndTiltBackOnRollingGround) {
  const auto target = ground(-8, 8, -6, 10, 0.05);
  Eigen::Isometry3d moved = Eigen::Isometry3d::Identity();
  moved.linear() = (Eigen::AngleAxisd(3 * M_PI / 180, Eigen::Vector3d::UnitZ()) *
                    Eigen::AngleAxisd(2 * M_PI / 180, Eigen::Vector3d(1, 1, 0).normalized()))
                       .toRotationMatrix();
  moved.translation() = Eigen::Vector3d(0.25, -0.15, 0.1);
  std::vector<Eigen::Vector3d> source;
  for (const auto& p : ground(-5, 6, -3, 8, 0.05)) source.push_back(moved * p);
  const Eigen::Isometry3d found = searchHeights(source, target);
  const Eigen::Isometry3d error = found * moved;  // identity when found undoes moved
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(5, 5, 0)})
    EXPECT_LT((error * p - p).norm(), 0.05) << p.transpose();
  EXPECT_LT(Eigen::AngleAxisd(error.linear()).angle(), 0.2 * M_PI / 180);
}

}  // namespace
}  // namespace ambler::mapping
