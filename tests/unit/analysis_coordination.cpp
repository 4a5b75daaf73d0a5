#include <gtest/gtest.h>

#include <cmath>

#include "granpack/analysis/coordination.h"

using namespace granpack;

namespace {
/// Runs the rattler iteration to its fixed point on one rank (all grains owned).
std::vector<std::uint8_t> rattlers(std::size_t n, const std::vector<CarryingContact>& c, int min) {
  std::vector<std::uint8_t> r(n, 0);
  std::vector<double> counts(n);
  do
    count_backbone_contacts(c, r, counts);
  while (flag_rattlers(n, counts, min, r) > 0);
  return r;
}
} // namespace

TEST(Coordination, IterationPeelsDanglingChains) {
  // A tetrahedron 0-1-2-3 (each grain 3 contacts) plus a chain 3-4-5: with min 2 (friction),
  // 5 has one contact -> rattler, then 4 has one -> rattler; the tetrahedron stays.
  std::vector<CarryingContact> c = {{0, 1, 1}, {0, 2, 1}, {0, 3, 1}, {1, 2, 1},
                                    {1, 3, 1}, {2, 3, 1}, {3, 4, 1}, {4, 5, 1}};
  auto r = rattlers(6, c, 2);
  EXPECT_EQ(r, (std::vector<std::uint8_t>{0, 0, 0, 0, 1, 1}));
  // With min 4 (frictionless 3D) every grain of the tetrahedron has 3: all are rattlers.
  auto r4 = rattlers(6, c, 4);
  for (auto f : r4)
    EXPECT_EQ(f, 1);
}

TEST(Coordination, HistogramCountsOnlyBackbone) {
  std::vector<CarryingContact> c = {{0, 1, 1}, {1, 2, 1}, {2, 0, 1}, {2, 3, 1}};
  auto r = rattlers(4, c, 2);
  std::vector<double> counts(4);
  count_backbone_contacts(c, r, counts);
  auto h = coordination_histogram(4, counts, r);
  ASSERT_EQ(h.size(), 3u);
  EXPECT_EQ(h[2], 3); // triangle: three divalent grains; grain 3 is a rattler
  EXPECT_EQ(r[3], 1);
}

TEST(Coordination, ForceMoments) {
  std::vector<CarryingContact> c = {{0, 1, 1.0}, {1, 2, 2.0}, {2, 3, 4.0}};
  EXPECT_DOUBLE_EQ(sum_force_power(c, 1.0), 7.0);
  EXPECT_DOUBLE_EQ(sum_force_power(c, 2.0), 21.0);
  // Z(2) = <N^2>/<N>^2 = 7 / (7/3)^2
  double z2 = (sum_force_power(c, 2.0) / 3) / std::pow(sum_force_power(c, 1.0) / 3, 2);
  EXPECT_NEAR(z2, 63.0 / 49.0, 1e-15);
}
