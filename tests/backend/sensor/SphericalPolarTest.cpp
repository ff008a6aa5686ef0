#include "sensor/SphericalPolar.h"

#include <gtest/gtest.h>

#include <random>

#include "core/Angles.h"
#include "sensor/RangeImage.h"

namespace ambler::sensor {
namespace {

TEST(SphericalPolar, Eq1AxesMatchThePaper) {
  // theta = phi = 0 looks along y; theta = 90 deg along x; phi = 90 deg along z.
  EXPECT_TRUE(toCartesian({2.0, 0.0, 0.0}).isApprox(Eigen::Vector3d(0, 2, 0)));
  EXPECT_NEAR((toCartesian({2.0, 0.0, M_PI / 2}) - Eigen::Vector3d(2, 0, 0)).norm(), 0, 1e-12);
  EXPECT_NEAR((toCartesian({2.0, M_PI / 2, 0.0}) - Eigen::Vector3d(0, 0, 2)).norm(), 0, 1e-12);
  // A generic point against eq. 1 written out.
  const double rho = 7.5, phi = -20 * kDeg, theta = 35 * kDeg;
  const auto p = toCartesian({rho, phi, theta});
  EXPECT_DOUBLE_EQ(p.x(), rho * std::sin(theta));
  EXPECT_DOUBLE_EQ(p.y(), rho * std::cos(phi) * std::cos(theta));
  EXPECT_DOUBLE_EQ(p.z(), rho * std::sin(phi) * std::cos(theta));
}

TEST(SphericalPolar, RoundTripTo1e9) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<> rho(0.1, 60.0), angle(-85 * kDeg, 85 * kDeg);
  for (int i = 0; i < 100000; ++i) {
    const SphericalPoint s{rho(rng), angle(rng), angle(rng)};
    const auto back = toSpherical(toCartesian(s));
    ASSERT_NEAR(back.rho, s.rho, 1e-9);
    ASSERT_NEAR(back.phi, s.phi, 1e-9);
    ASSERT_NEAR(back.theta, s.theta, 1e-9);
    const Eigen::Vector3d p(rho(rng) - 30, rho(rng), rho(rng) - 30);
    ASSERT_LT((toCartesian(toSpherical(p)) - p).norm(), 1e-9);
  }
}

TEST(ScanGeometry, SymmetricGeometrySpansTheFieldOfView) {
  const auto g = ScanGeometry::symmetric(64, 256, 30 * kDeg, 80 * kDeg);
  // Pixel centres sit half a pixel inside the field of view's edges.
  EXPECT_NEAR(g.phi(-0.5), 15 * kDeg, 1e-12);
  EXPECT_NEAR(g.phi(63.5), -15 * kDeg, 1e-12);
  EXPECT_NEAR(g.theta(-0.5), -40 * kDeg, 1e-12);
  EXPECT_NEAR(g.theta(255.5), 40 * kDeg, 1e-12);
  EXPECT_NEAR(g.row(g.phi(17.25)), 17.25, 1e-9);
  EXPECT_NEAR(g.col(g.theta(3.5)), 3.5, 1e-9);
  EXPECT_TRUE(g.covers(0.0, 0.0));
  EXPECT_FALSE(g.covers(16 * kDeg, 0.0));
  EXPECT_FALSE(g.covers(0.0, -41 * kDeg));
}

TEST(NoiseModel, SigmaGrowsWithTheSquareOfRange) {
  EXPECT_DOUBLE_EQ(rangeSigma(10.0, 2e-4), 0.02);
  EXPECT_DOUBLE_EQ(rangeSigma(20.0, 2e-4), 0.08);
  EXPECT_DOUBLE_EQ(rangeSigma(20.0, 0.0), 0.0);
}

}  // namespace
}  // namespace ambler::sensor
