#include "core/GridSpec.h"

#include <gtest/gtest.h>

#include <cmath>

namespace ambler {
namespace {

const Box2 kBox{-2.0, 1.0, 4.0, 5.0};

// Rows and columns from 0 to one short of the count, and nothing beyond.
TEST(GridSpecHasCell, OnlyTheGridsOwnRowsAndColumns) {
  GridSpec g;
  g.rows = 3;
  g.cols = 5;
  EXPECT_TRUE(g.hasCell(0, 0));
  EXPECT_TRUE(g.hasCell(2, 4));
  EXPECT_FALSE(g.hasCell(-1, 0));
  EXPECT_FALSE(g.hasCell(0, -1));
  EXPECT_FALSE(g.hasCell(3, 0));
  EXPECT_FALSE(g.hasCell(0, 5));
}

TEST(Box2LineInterval, FromInsideItEndsAtTheEdgeAhead) {
  const auto east = kBox.lineInterval({1.0, 3.0}, {1.0, 0.0}, INFINITY);
  ASSERT_TRUE(east);
  EXPECT_DOUBLE_EQ(east->first, 0.0);
  EXPECT_DOUBLE_EQ(east->second, 3.0);
  // Along the diagonal (0.6, 0.8) from (1, 3): y leaves at t = 2.5, before x (t = 5).
  const auto slanted = kBox.lineInterval({1.0, 3.0}, {0.6, 0.8}, INFINITY);
  ASSERT_TRUE(slanted);
  EXPECT_DOUBLE_EQ(slanted->second, 2.5);
}

TEST(Box2LineInterval, FromOutsideItEntersAndLeaves) {
  const auto crossing = kBox.lineInterval({-5.0, 2.0}, {1.0, 0.0}, 100.0);
  ASSERT_TRUE(crossing);
  EXPECT_DOUBLE_EQ(crossing->first, 3.0);
  EXPECT_DOUBLE_EQ(crossing->second, 9.0);
  // Cut short by t_max.
  EXPECT_DOUBLE_EQ(kBox.lineInterval({-5.0, 2.0}, {1.0, 0.0}, 4.0)->second, 4.0);
}

TEST(Box2LineInterval, ALineThatMissesTheBoxHasNone) {
  EXPECT_FALSE(kBox.lineInterval({-5.0, 2.0}, {-1.0, 0.0}, INFINITY));   // away from it
  EXPECT_FALSE(kBox.lineInterval({-5.0, 2.0}, {1.0, 0.0}, 2.0));         // stops short
  EXPECT_FALSE(kBox.lineInterval({-5.0, 7.0}, {1.0, 0.0}, INFINITY));    // parallel, above
  EXPECT_FALSE(kBox.lineInterval({-5.0, 0.0}, {1.0, 1e-13}, INFINITY));  // as good as parallel
}

}  // namespace
}  // namespace ambler
