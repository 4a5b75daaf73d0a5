// Cut planes of the domain decomposition's load balancing (core/cut_planes.h): quantiles of a
// histogram, the minimum slab width, and the limits (empty histogram, everything in one bin).
#include "granpack/core/cut_planes.h"

#include <gtest/gtest.h>

#include <vector>

using namespace granpack;

namespace {
std::vector<std::int64_t> histogram(std::size_t bins, std::size_t from, std::size_t to,
                                    std::int64_t per_bin) {
  std::vector<std::int64_t> h(bins, 0);
  for (std::size_t b = from; b < to; ++b)
    h[b] = per_bin;
  return h;
}
} // namespace

TEST(CutPlanes, UniformCutsAreTheStaticGrid) {
  const std::vector<double> c = uniform_cuts(3);
  ASSERT_EQ(c.size(), 4u);
  EXPECT_EQ(c[0], 0.0);
  EXPECT_EQ(c[1], 1.0 / 3);
  EXPECT_EQ(c[2], 2.0 / 3);
  EXPECT_EQ(c[3], 1.0);
  EXPECT_DOUBLE_EQ(narrowest_slab(c), 1.0 / 3);
}

TEST(CutPlanes, EvenWeightGivesUniformCuts) {
  const auto h = histogram(400, 0, 400, 7);
  const std::vector<double> c = quantile_cuts(h, 4, 0.0);
  ASSERT_EQ(c.size(), 5u);
  for (int k = 0; k <= 4; ++k)
    EXPECT_NEAR(c[k], k / 4.0, 1e-15) << k;
}

TEST(CutPlanes, CutsFollowTheGrains) {
  // Weight only in [0.5, 0.75): two slabs split it at 0.625, the median.
  const auto h = histogram(400, 200, 300, 3);
  const std::vector<double> two = quantile_cuts(h, 2, 0.0);
  EXPECT_NEAR(two[1], 0.625, 1e-15);
  // Four slabs: cuts at the quartiles of the occupied band.
  const std::vector<double> four = quantile_cuts(h, 4, 0.0);
  EXPECT_NEAR(four[1], 0.5625, 1e-15);
  EXPECT_NEAR(four[2], 0.625, 1e-15);
  EXPECT_NEAR(four[3], 0.6875, 1e-15);
}

TEST(CutPlanes, InterpolatesInsideABin) {
  // 10 grains in bin 0 of 2 and 30 in bin 1: half of 40 is reached 10/30 into bin 1.
  const std::vector<std::int64_t> h{10, 30};
  const std::vector<double> c = quantile_cuts(h, 2, 0.0);
  EXPECT_NEAR(c[1], 0.5 + 0.5 * (10.0 / 30.0), 1e-15);
}

TEST(CutPlanes, SlabsAreAtLeastTheMinimumWidth) {
  // Everything in one narrow band: the quantiles would give slabs of 1/300 of the cell; the
  // minimum width 0.2 widens them around the band, and no slab is narrower.
  const auto h = histogram(300, 100, 102, 50);
  const std::vector<double> c = quantile_cuts(h, 4, 0.2);
  ASSERT_EQ(c.size(), 5u);
  EXPECT_GE(narrowest_slab(c), 0.2 - 1e-15);
  EXPECT_EQ(c.front(), 0.0);
  EXPECT_EQ(c.back(), 1.0);
  for (std::size_t k = 0; k + 1 < c.size(); ++k)
    EXPECT_LT(c[k], c[k + 1]);
  // The first quartile of the band (1/4 into it) keeps its place; the planes above it move
  // up by the minimum width, so the band is shared by two slabs (1/4 and 3/4), not one.
  EXPECT_NEAR(c[1], (100.0 + 0.5) / 300, 1e-15);
  EXPECT_NEAR(c[2], c[1] + 0.2, 1e-15);
  EXPECT_NEAR(c[3], c[2] + 0.2, 1e-15);
  // When the widths leave no freedom, the cuts are the uniform ones.
  const std::vector<double> tight = quantile_cuts(h, 4, 0.25);
  for (int k = 0; k <= 4; ++k)
    EXPECT_NEAR(tight[k], k / 4.0, 1e-15) << k;
}

TEST(CutPlanes, EmptyHistogramGivesUniformCuts) {
  const std::vector<std::int64_t> h(64, 0);
  EXPECT_EQ(quantile_cuts(h, 3, 0.1), uniform_cuts(3));
}

TEST(CutPlanes, RefusesSlabsThatDoNotFit) {
  const std::vector<std::int64_t> h(64, 1);
  EXPECT_ANY_THROW(quantile_cuts(h, 4, 0.3));
}

TEST(CutPlanes, MinmaxWithOneColumnBalancesTheSlabs) {
  // Two slabs over 8 bins: the fullest slab is smallest (120 of 200) with the cut after bin 2
  // or 3; checked against every possible cut.
  const std::vector<std::int64_t> h{40, 40, 40, 40, 10, 10, 10, 10};
  const std::vector<double> c = minmax_cuts(h, 1, 2, 0.0);
  ASSERT_EQ(c.size(), 3u);
  auto fullest = [&](int cut) {
    std::int64_t left = 0, right = 0;
    for (int b = 0; b < 8; ++b)
      (b < cut ? left : right) += h[b];
    return std::max(left, right);
  };
  std::int64_t best = 1 << 30;
  for (int cut = 1; cut < 8; ++cut)
    best = std::min(best, fullest(cut));
  EXPECT_EQ(best, 120);
  EXPECT_EQ(fullest(static_cast<int>(c[1] * 8 + 0.5)), best) << "cut at " << c[1];
}

TEST(CutPlanes, MinmaxBalancesCellsWhereQuantilesCannot) {
  // Two columns (the other axis' slabs), 4 bins along this axis, 2 slabs; h[bin * 2 + column].
  // Column 1 holds 20 and 40 in bins 0 and 1, column 0 holds 30 in bin 3. The quantile of the
  // axis totals (20, 40, 0, 30) falls in bin 1 and leaves bins 0 and 1 of column 1 in one cell
  // (60); cutting after bin 0 gives no cell above 40.
  const std::vector<std::int64_t> h{0, 20, 0, 40, 0, 0, 30, 0};
  const std::vector<double> q = quantile_cuts(std::vector<std::int64_t>{20, 40, 0, 30}, 2, 0.0);
  const std::vector<double> m = minmax_cuts(h, 2, 2, 0.0);
  auto fullest = [&](double cut) {
    std::int64_t cell[2][2] = {{0, 0}, {0, 0}};
    for (int b = 0; b < 4; ++b)
      for (int col = 0; col < 2; ++col)
        cell[(b + 0.5) / 4 < cut ? 0 : 1][col] += h[b * 2 + col];
    return std::max({cell[0][0], cell[0][1], cell[1][0], cell[1][1]});
  };
  EXPECT_EQ(fullest(q[1]), 60) << "quantile cut at " << q[1];
  EXPECT_EQ(fullest(m[1]), 40) << "min-max cut at " << m[1];
}

TEST(CutPlanes, MinmaxKeepsTheMinimumWidth) {
  // Everything in one bin of 64. Four slabs of at least 0.25: the uniform cuts.
  std::vector<std::int64_t> h(64, 0);
  h[5] = 100;
  EXPECT_EQ(minmax_cuts(h, 1, 4, 0.25), uniform_cuts(4));
  // Of at least 0.1: every slab is, and the planes span the cell.
  const std::vector<double> w = minmax_cuts(h, 1, 4, 0.1);
  EXPECT_GE(narrowest_slab(w), 0.1);
  EXPECT_EQ(w.front(), 0.0);
  EXPECT_EQ(w.back(), 1.0);
}
