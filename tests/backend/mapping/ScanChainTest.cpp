// A walk's scans chained by registration: the second view, placed 0.3 m
// and 3 degrees off by dead reckoning, is pulled back onto the first.
#include "mapping/ScanChain.h"

#include <gtest/gtest.h>

#include <cmath>

#include "backend/mapping/SimulatedView.h"

namespace ambler::mapping {
namespace {

Cloud inWorld(const test::View& v, const Eigen::Isometry3d& pose) {
  Cloud out;
  for (const auto& p : v.points) out.push_back(pose * p);
  return out;
}

TEST(ScanChain, EachScanIsRegisteredAgainstTheOneBefore) {
  const auto a = test::viewFrom(1, {0, 0}, 0), b = test::viewFrom(1, {0.4, 2.5}, 6 * M_PI / 180);
  const Eigen::Isometry3d drift = Eigen::Translation3d(0.3, -0.2, 0.0) *
                                  Eigen::AngleAxisd(3 * M_PI / 180, Eigen::Vector3d::UnitZ());
  ScanChain chain;
  chain.add(inWorld(a, a.pose), a.pose.translation());
  // Where dead reckoning put it.
  chain.add(inWorld(b, drift * b.pose), (drift * b.pose).translation());
  const auto job = chain.next();
  ASSERT_TRUE(job.has_value());  // the first became the reference
  EXPECT_EQ(chain.registered().size(), 1u);
  EXPECT_TRUE(chain.busy());
  EXPECT_FALSE(chain.next().has_value());  // one at a time
  chain.finish(ScanChain::run(*job));
  ASSERT_EQ(chain.registered().size(), 2u);
  EXPECT_TRUE(chain.last().converged);
  // Each point of b lands within 3 cm of where it truly is.
  const Cloud truth = inWorld(b, b.pose);
  double worst = 0.0;
  for (std::size_t i = 0; i < truth.size(); i += 97)
    worst = std::max(worst, (chain.registered()[1][i] - truth[i]).norm());
  EXPECT_LT(worst, 0.03) << worst << " m";
  EXPECT_EQ(chain.merged().size(), a.points.size() + b.points.size());
}

TEST(ScanChain, AJobClearedWhileItRanFinishesIntoNothing) {
  ScanChain chain;
  chain.add({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {0, 0, 5});
  chain.add({{0, 0, 0.1}}, {0, 0, 5});
  const auto job = chain.next();
  ASSERT_TRUE(job.has_value());
  const auto result = ScanChain::run(*job);  // too few points: identity
  EXPECT_FALSE(result.converged);
  chain.clear();
  chain.finish(result);
  EXPECT_TRUE(chain.registered().empty());
  EXPECT_FALSE(chain.busy());
}

}  // namespace
}  // namespace ambler::mapping
