#include "link/Link.h"

#include <gtest/gtest.h>

namespace ambler::link {
namespace {

TEST(LinkHealth, StaleWithoutDataAndAfterTheTimeout) {
  LinkHealth health(3.0);
  EXPECT_TRUE(health.stale(0.0));
  EXPECT_FALSE(health.ageS(0.0).has_value());
  health.heard(10.0);
  EXPECT_FALSE(health.stale(12.9));
  EXPECT_DOUBLE_EQ(*health.ageS(12.5), 2.5);
  EXPECT_TRUE(health.stale(13.1));
}

}  // namespace
}  // namespace ambler::link
