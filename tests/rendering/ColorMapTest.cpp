#include "rendering/ColorMap.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace ambler::rendering {
namespace {

TEST(ColorBarTicks, AMapOfTwentyNineCentimetresGetsTenthsOfAMetre) {
  // The terrain map's range before: labels at -0.19, -0.11, -0.03, 0.06, 0.14.
  const auto ticks = colorBarTicks(-0.19, 0.14);
  EXPECT_EQ(ticks.values, (std::vector<double>{-0.15, -0.1, -0.05, 0.0, 0.05, 0.1}));
  EXPECT_EQ(ticks.decimals, 2);
}

TEST(ColorBarTicks, ZeroIsExactlyZeroSoItNeverPrintsAsMinusZero) {
  const auto ticks = colorBarTicks(-0.104, 0.31);
  ASSERT_EQ(ticks.values.size(), 5u);
  EXPECT_EQ(ticks.values[1], 0.0);
  EXPECT_FALSE(std::signbit(ticks.values[1]));
  EXPECT_DOUBLE_EQ(ticks.values.front(), -0.1);
  EXPECT_DOUBLE_EQ(ticks.values.back(), 0.3);
}

TEST(ColorBarTicks, RangesInMetresGetWholeMetresAndNoDecimals) {
  const auto ticks = colorBarTicks(7.2, 19.2);
  EXPECT_EQ(ticks.values, (std::vector<double>{8, 10, 12, 14, 16, 18}));
  EXPECT_EQ(ticks.decimals, 0);
}

TEST(ColorBarTicks, TheDangerScaleGetsFifthsWithOneDecimal) {
  const auto ticks = colorBarTicks(0.0, 1.0);
  EXPECT_EQ(ticks.values.size(), 6u);
  EXPECT_DOUBLE_EQ(ticks.values[3], 0.6);
  EXPECT_EQ(ticks.decimals, 1);
}

TEST(ColorBarTicks, EveryLabelLiesInsideTheBarAndTheyAreNeverTooMany) {
  for (double lo = -3.0; lo < 3.0; lo += 0.37)
    for (double span : {1e-3, 0.013, 0.29, 1.0, 4.7, 55.0, 1234.0}) {
      const auto ticks = colorBarTicks(lo, lo + span, 6);
      ASSERT_GE(ticks.values.size(), 2u) << lo << " + " << span;
      ASSERT_LE(ticks.values.size(), 6u) << lo << " + " << span;
      for (double v : ticks.values) {
        EXPECT_GE(v, lo - 1e-9 * span);
        EXPECT_LE(v, lo + span + 1e-9 * span);
      }
      // Labels that differ must print differently at the decimals given.
      const double step = ticks.values[1] - ticks.values[0];
      EXPECT_GE(step * std::pow(10.0, ticks.decimals), 1.0 - 1e-9);
    }
}

TEST(ColorBarTicks, AFlatOrMissingRangeGetsOneLabelOrNone) {
  EXPECT_EQ(colorBarTicks(0.25, 0.25).values, std::vector<double>{0.25});
  EXPECT_TRUE(colorBarTicks(1.0, 0.0).values.empty());
  EXPECT_TRUE(colorBarTicks(std::numeric_limits<double>::quiet_NaN(), 1.0).values.empty());
  EXPECT_TRUE(colorBarTicks(0.0, std::numeric_limits<double>::infinity()).values.empty());
}

}  // namespace
}  // namespace ambler::rendering
