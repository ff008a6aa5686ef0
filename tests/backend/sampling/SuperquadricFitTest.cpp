// Superquadric recovery (cmu-1990 sampling paper §3.2, after Solina):
// analytic cases with known parameters.
#include "sampling/SuperquadricFit.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

namespace ambler::sampling {
namespace {

Superquadric rock() {
  Superquadric s;
  s.size = {0.06, 0.04, 0.03};
  s.eps1 = 0.6;
  s.eps2 = 0.8;
  s.pose = Eigen::Translation3d(0.1, -0.2, 0.02) *
           Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()) *
           Eigen::AngleAxisd(0.15, Eigen::Vector3d::UnitX());
  return s;
}

// Points on the surface from the superquadric's parametric form, above
// `min_eta` in latitude (a view from above sees only the top).
std::vector<Eigen::Vector3d> surface(const Superquadric& s, double min_eta, double noise,
                                     unsigned seed = 1) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, noise);
  std::vector<Eigen::Vector3d> out;
  for (int i = 0; i < 40; ++i)
    for (int k = 0; k < 50; ++k) {
      const double eta = min_eta + (M_PI / 2 - min_eta) * (i + 0.5) / 40;
      const double omega = -M_PI + 2 * M_PI * (k + 0.5) / 50;
      out.push_back(s.surfacePoint(eta, omega) + Eigen::Vector3d(n(rng), n(rng), n(rng)));
    }
  return out;
}

TEST(SuperquadricFit, SizeErrorsMatchAxesByDirection) {
  const auto truth = rock();
  Superquadric renamed = truth;  // x and y swapped: the same box
  renamed.size = {truth.size.y(), truth.size.x(), truth.size.z()};
  renamed.pose = truth.pose * Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ());
  EXPECT_NEAR(sizeError(renamed, truth), 0.0, 1e-12);
  Superquadric bigger = truth;
  bigger.size.z() *= 1.2;
  EXPECT_NEAR(sizeError(bigger, truth), 0.2, 1e-12);
}

TEST(SuperquadricFit, TheInsideOutsideFunctionIsOneOnTheSurface) {
  const auto s = rock();
  for (const auto& p : surface(s, -M_PI / 2, 0.0)) EXPECT_NEAR(s.insideOutside(p), 1.0, 1e-9);
}

// The support function against the farthest of a dense sample of the
// surface, and the ellipsoid's closed form.
TEST(Superquadric, ReachIsTheFarthestSurfacePointAlongADirection) {
  std::mt19937 rng(3);
  std::normal_distribution<double> n(0.0, 1.0);
  for (const auto& [eps1, eps2] : {std::pair{0.6, 0.8}, {0.2, 0.3}, {1.0, 1.0}, {1.8, 1.5}}) {
    Superquadric s = rock();
    s.eps1 = eps1, s.eps2 = eps2;
    for (int trial = 0; trial < 20; ++trial) {
      const Eigen::Vector3d d = Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
      double farthest = 0;
      for (int i = 0; i <= 200; ++i)
        for (int k = 0; k < 400; ++k) {
          const Eigen::Vector3d p =
              s.surfacePoint(-M_PI / 2 + M_PI * i / 200, -M_PI + M_PI * k / 200);
          farthest = std::max(farthest, d.dot(p - s.pose.translation()));
        }
      EXPECT_GE(s.reach(d), farthest - 1e-9) << eps1 << " " << eps2;
      EXPECT_NEAR(s.reach(d), farthest, 2e-3 * s.size.maxCoeff()) << eps1 << " " << eps2;
      if (eps1 == 1.0 && eps2 == 1.0) {
        const Eigen::Vector3d u = s.pose.linear().transpose() * d;
        EXPECT_NEAR(s.reach(d), s.size.cwiseProduct(u).norm(), 1e-12);
      }
    }
  }
}

TEST(SuperquadricFit, RecoversAWholeSuperquadricWithEitherResidual) {
  const auto truth = rock();
  FitOptions solina;
  solina.residual = FitResidual::kSolina;
  const auto paper = fitSuperquadric(surface(truth, -M_PI / 2, 0.0), solina);
  EXPECT_LT(sizeError(paper.shape, truth), 0.01);
  EXPECT_LT((paper.shape.pose.translation() - truth.pose.translation()).norm(), 1e-3);
  const auto fit = fitSuperquadric(surface(truth, -M_PI / 2, 0.0));
  EXPECT_TRUE(fit.converged);
  EXPECT_LT(sizeError(fit.shape, truth), 0.01);
  EXPECT_LT((fit.shape.pose.translation() - truth.pose.translation()).norm(), 1e-3);
  EXPECT_NEAR(fit.shape.eps1, truth.eps1, 0.05);
  EXPECT_NEAR(fit.shape.eps2, truth.eps2, 0.05);
  EXPECT_LT(fit.rms_m, 1e-4);
}

// The upper two thirds, with 0.5 mm noise: what the striper sees of a rock
// lying on the sand.
TEST(SuperquadricFit, RecoversTheRockFromItsVisibleTop) {
  const auto truth = rock();
  const auto fit = fitSuperquadric(surface(truth, -M_PI / 6, 0.0005));
  EXPECT_LT(sizeError(fit.shape, truth), 0.10);
  EXPECT_LT((fit.shape.pose.translation() - truth.pose.translation()).norm(), 0.005);
}

// 20 % of the points are stray: plain least squares is pulled away, the
// robust fit is not.
TEST(SuperquadricFit, TheRobustFitIgnoresOutliers) {
  const auto truth = rock();
  auto points = surface(truth, -M_PI / 6, 0.0005);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.12, 0.12);
  const std::size_t clean = points.size();
  for (std::size_t i = 0; i < clean / 4; ++i)
    points.push_back(truth.pose.translation() + Eigen::Vector3d(u(rng), u(rng), 0.5 * u(rng)));
  const auto plain = fitSuperquadric(points);
  FitOptions robust_options;
  robust_options.robust = true;
  const auto robust = fitSuperquadric(points, robust_options);
  EXPECT_LT(sizeError(robust.shape, truth), 0.10);
  EXPECT_LT((robust.shape.pose.translation() - truth.pose.translation()).norm(), 0.005);
  EXPECT_GT(sizeError(plain.shape, truth), 0.10);
  EXPECT_NEAR(robust.inlier_share, double(clean) / double(points.size()), 0.05);
}

TEST(SuperquadricFit, BadInputIsRefusedWithTheProblemNamed) {
  EXPECT_THROW(
      {
        try {
          fitSuperquadric(std::vector<Eigen::Vector3d>(5, Eigen::Vector3d::Zero()));
        } catch (const std::invalid_argument& e) {
          EXPECT_NE(std::string(e.what()).find("at least 11"), std::string::npos);
          throw;
        }
      },
      std::invalid_argument);
  auto points = surface(rock(), 0, 0);
  points[3].x() = NAN;
  EXPECT_THROW(fitSuperquadric(points), std::invalid_argument);
  FitOptions bad;
  bad.max_iterations = 0;
  EXPECT_THROW(fitSuperquadric(surface(rock(), 0, 0), bad), std::invalid_argument);
}

}  // namespace
}  // namespace ambler::sampling
