// Nearest-neighbour queries against brute force over random points.
#include "mapping/PointIndex.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace ambler::mapping {
namespace {

std::vector<Eigen::Vector3f> randomPoints(int n, std::mt19937& rng) {
  std::uniform_real_distribution<float> u(-5.0f, 5.0f);
  std::vector<Eigen::Vector3f> out;
  for (int i = 0; i < n; ++i) out.emplace_back(u(rng), u(rng), 0.1f * u(rng));
  return out;
}

PointIndex::Hit bruteForce(const std::vector<Eigen::Vector3f>& points, const Eigen::Vector3f& q,
                           float max_distance2) {
  PointIndex::Hit best;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const float d2 = (points[i] - q).squaredNorm();
    if (d2 <= max_distance2 && (best.index < 0 || d2 < best.distance2)) best = {int(i), d2};
  }
  return best;
}

// The answer is the nearest point within the limit, or none; with its lead,
// the distance from the query to the next point within the limit (or the
// limit) less the nearest's.
TEST(PointIndex, TheNearestPointAndItsLeadAreThoseOfBruteForce) {
  std::mt19937 rng(7);
  const auto points = randomPoints(5000, rng);
  const PointIndex index(points);
  std::uniform_real_distribution<float> u(-6.0f, 6.0f);
  int found = 0, none = 0, alone = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const Eigen::Vector3f q(u(rng), u(rng), 0.2f * u(rng));
    const float limit2 = trial % 2 ? 0.01f : 0.04f;
    const auto truth = bruteForce(points, q, limit2);
    truth.index < 0 ? ++none : ++found;
    const auto hit = index.nearest(q, limit2);
    ASSERT_EQ(hit.index, truth.index) << "trial " << trial;
    float lead = -1.0f;
    ASSERT_EQ(index.nearestWithLead(q, limit2, lead).index, truth.index) << "trial " << trial;
    if (truth.index < 0) continue;
    EXPECT_FLOAT_EQ(hit.distance2, truth.distance2);
    float next2 = limit2;
    for (std::size_t i = 0; i < points.size(); ++i)
      if (int(i) != truth.index) next2 = std::min(next2, (points[i] - q).squaredNorm());
    alone += next2 == limit2;
    EXPECT_NEAR(lead, std::sqrt(next2) - std::sqrt(truth.distance2), 1e-6f) << "trial " << trial;
  }
  // Every outcome was exercised.
  EXPECT_GT(found, 200);
  EXPECT_GT(none, 200);
  EXPECT_GT(alone, 20);
}

// A query moved in any direction by up to half its lead keeps its nearest
// point: what lets GICP skip the search between small steps.
TEST(PointIndex, AQueryMovedByUnderHalfItsLeadKeepsItsNearestPoint) {
  std::mt19937 rng(11);
  const auto points = randomPoints(5000, rng);
  const PointIndex index(points);
  std::uniform_real_distribution<float> u(-5.0f, 5.0f);
  std::normal_distribution<float> n(0.0f, 1.0f);
  int moved = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const Eigen::Vector3f q(u(rng), u(rng), 0.1f * u(rng));
    float lead = 0.0f;
    const auto hit = index.nearestWithLead(q, 0.04f, lead);
    if (hit.index < 0 || lead < 1e-3f) continue;
    const Eigen::Vector3f away =
        q + Eigen::Vector3f(n(rng), n(rng), n(rng)).normalized() * (0.499f * lead);
    ASSERT_EQ(bruteForce(points, away, 1.0f).index, hit.index) << "trial " << trial;
    ++moved;
  }
  EXPECT_GT(moved, 500);
}

}  // namespace
}  // namespace ambler::mapping
