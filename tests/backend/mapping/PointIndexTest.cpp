// Nearest-neighbour queries against brute force over random points.
#include "mapping/PointIndex.h"

#include <gtest/gtest.h>

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

// Whatever the hint (none, the answer itself, a near point, a point
// beyond the limit, an index out of range), the answer is the nearest
// point within the limit, or none.
TEST(PointIndex, AHintNeverChangesTheNearestPoint) {
  std::mt19937 rng(7);
  const auto points = randomPoints(5000, rng);
  const PointIndex index(points);
  std::uniform_real_distribution<float> u(-6.0f, 6.0f);
  std::uniform_int_distribution<int> any(0, int(points.size()) - 1);
  int found = 0, none = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const Eigen::Vector3f q(u(rng), u(rng), 0.2f * u(rng));
    const float limit2 = trial % 2 ? 0.01f : 0.04f;
    const auto truth = bruteForce(points, q, limit2);
    truth.index < 0 ? ++none : ++found;
    for (const int hint : {-1, truth.index, any(rng), int(points.size()), 1 << 30}) {
      const auto hit = index.nearest(q, limit2, hint);
      ASSERT_EQ(hit.index, truth.index) << "trial " << trial << " hint " << hint;
      if (hit.index >= 0) {
        EXPECT_FLOAT_EQ(hit.distance2, truth.distance2);
      }
    }
  }
  // Both outcomes were exercised.
  EXPECT_GT(found, 200);
  EXPECT_GT(none, 200);
}

}  // namespace
}  // namespace ambler::mapping
