#include <gtest/gtest.h>

#include "granpack/core/cell.h"

using namespace granpack;

TEST(Cell, MinimumImageCrossesThePeriodicBoundary) {
  Cell<3> cell;
  cell.length = Vec<3>(2.0, 3.0, 4.0);
  Vec<3> si(0.95, 0.5, 0.02), sj(0.05, 0.5, 0.98);
  Vec<3> r = cell.min_image(si, sj);
  EXPECT_NEAR(r[0], 0.2, 1e-14);
  EXPECT_NEAR(r[1], 0.0, 1e-14);
  EXPECT_NEAR(r[2], -0.16, 1e-14);
  EXPECT_DOUBLE_EQ(cell.volume(), 24.0);
}

TEST(Cell, WrapKeepsScaledPositionsInUnitBox) {
  Vec<2> s = Cell<2>::wrap(Vec<2>(-1e-18, 1.25));
  EXPECT_GE(s[0], 0.0);
  EXPECT_LT(s[0], 1.0);
  EXPECT_DOUBLE_EQ(s[1], 0.25);
}
