// Registration of simulated scans taken from different viewpoints (known
// poses), bakambu-csa §2.
#include "mapping/Registration.h"

#include <gtest/gtest.h>

#include <cmath>

#include "backend/mapping/SimulatedView.h"

namespace ambler::mapping {
namespace {

using test::View;
using test::viewFrom;

Eigen::Isometry3d perturbed(const Eigen::Isometry3d& t, double metres, double degrees) {
  return t * Eigen::Translation3d(metres, -metres, 0.3 * metres) *
         Eigen::AngleAxisd(degrees * M_PI / 180, Eigen::Vector3d(0.2, 0.1, 1).normalized());
}

// Two views 2.5 m apart with a 6 degree turn, dead reckoning off by 0.3 m
// and 3 degrees: ICP lands within 1 % of the distance travelled.
TEST(Registration, IcpAlignsScansFromTwoViewpoints) {
  const View a = viewFrom(1, {0, 0}, 0), b = viewFrom(1, {0.4, 2.5}, 6 * M_PI / 180);
  const Eigen::Isometry3d truth = a.pose.inverse() * b.pose;  // b's frame -> a's
  const auto r = registerIcp(b.points, a.points, perturbed(truth, 0.3, 3.0));
  const double travelled = (b.pose.translation() - a.pose.translation()).norm();
  const double error = (r.transform.translation() - truth.translation()).norm();
  EXPECT_TRUE(r.converged);
  EXPECT_LT(error, 0.01 * travelled) << error << " m of " << travelled << " m";
  EXPECT_LT(Eigen::AngleAxisd(r.transform.linear().transpose() * truth.linear()).angle(),
            0.2 * M_PI / 180);
}

TEST(Registration, BadInputIsRefusedWithTheProblemNamed) {
  const Cloud few{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const View a = viewFrom(2, {0, 0}, 0);
  EXPECT_THROW(
      {
        try {
          registerIcp(few, a.points, Eigen::Isometry3d::Identity());
        } catch (const std::invalid_argument& e) {
          EXPECT_NE(std::string(e.what()).find("the source has"), std::string::npos) << e.what();
          throw;
        }
      },
      std::invalid_argument);
  Cloud bad = a.points;
  bad[5].y() = NAN;
  EXPECT_THROW(registerIcp(bad, a.points, Eigen::Isometry3d::Identity()), std::invalid_argument);
  IcpOptions options;
  options.voxel_m = 0;
  EXPECT_THROW(registerIcp(a.points, a.points, Eigen::Isometry3d::Identity(), options),
               std::invalid_argument);
}

}  // namespace
}  // namespace ambler::mapping
