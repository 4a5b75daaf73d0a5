// Kernels of the cohesive force statistics (include/granpack/analysis/interaction_forces.h):
// the percolation threshold on hand-built periodic networks whose answer is known, the
// histogram bookkeeping, the force angle and Rumpf's formula on closed forms.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "granpack/analysis/interaction_forces.h"

namespace granpack {
namespace {

/// An m x m periodic square network: bond (x, y)-(x+1, y) has force fx, (x, y)-(x, y+1) fy;
/// the bonds across the cell boundary carry the image shift.
std::vector<PercolationEdge<2>> square(int m, double fx, double fy) {
  std::vector<PercolationEdge<2>> e;
  auto id = [m](int x, int y) { return std::int64_t((x % m) + m * (y % m)); };
  for (int y = 0; y < m; ++y)
    for (int x = 0; x < m; ++x) {
      e.push_back({id(x, y), id(x + 1, y), {x + 1 == m ? 1 : 0, 0}, fx});
      e.push_back({id(x, y), id(x, y + 1), {0, y + 1 == m ? 1 : 0}, fy});
    }
  return e;
}

TEST(Percolation, RowsWrapFirstThenTheWholeNetwork) {
  // Horizontal bonds carry 2, vertical ones 1: rows wrap along x at F = 2, both directions
  // are spanned only once vertical bonds come in, at F = 1.
  const auto r = percolation_threshold<2>(square(6, 2.0, 1.0), 36);
  EXPECT_EQ(r.threshold_any, 2.0);
  EXPECT_EQ(r.threshold_all, 1.0);
  EXPECT_EQ(r.edges_at_any, 6); // the first row closes with its 6th bond (ties sorted by id)
}

TEST(Percolation, OneWeakBondPerRowDelaysWrapping) {
  auto e = square(5, 3.0, 0.5);
  // Weaken one horizontal bond of every row: no row wraps before F = 1.5.
  for (auto& b : e)
    if (b.shift[0] == 1)
      b.force = 1.5;
  const auto r = percolation_threshold<2>(e, 25);
  EXPECT_EQ(r.threshold_any, 1.5);
  EXPECT_EQ(r.threshold_all, 0.5);
}

TEST(Percolation, ClosedLoopsInsideTheCellDoNotWrap) {
  // A ring of 4 grains (a square cycle with zero net shift) and a dangling chain: no wrapping.
  std::vector<PercolationEdge<3>> e = {{0, 1, {0, 0, 0}, 1.0}, {1, 2, {0, 0, 0}, 1.0},
                                       {2, 3, {0, 0, 0}, 1.0}, {3, 0, {0, 0, 0}, 1.0},
                                       {3, 4, {0, 0, 0}, 0.5}, {4, 5, {1, 0, 0}, 0.2}};
  const auto r = percolation_threshold<3>(e, 6);
  EXPECT_EQ(r.threshold_any, 0.0);
  EXPECT_EQ(r.threshold_all, 0.0);
  // Closing the chain back onto the ring through a boundary makes it wrap along x at 0.1.
  e.push_back({5, 0, {0, 0, 0}, 0.1});
  const auto w = percolation_threshold<3>(e, 6);
  EXPECT_EQ(w.threshold_any, 0.1);
  EXPECT_EQ(w.threshold_all, 0.0); // only x is spanned
}

TEST(Percolation, ResultDoesNotDependOnEdgeOrder) {
  auto e = square(7, 1.0, 1.0);
  for (std::size_t k = 0; k < e.size(); ++k)
    e[k].force = 1.0 + double((k * 37) % 11);
  const auto a = percolation_threshold<2>(e, 49);
  std::reverse(e.begin(), e.end());
  const auto b = percolation_threshold<2>(e, 49);
  EXPECT_EQ(a.threshold_any, b.threshold_any);
  EXPECT_EQ(a.threshold_all, b.threshold_all);
  EXPECT_GT(a.threshold_any, 0.0);
}

TEST(Histogram, CountsBinsAndTails) {
  Histogram h(-1.0, 1.0, 4);
  for (double x : {-2.0, -1.0, -0.6, 0.0, 0.49, 0.5, 0.99, 1.0, 3.0})
    h.add(x);
  EXPECT_EQ(h.below, 1.0);
  EXPECT_EQ(h.above, 2.0);
  EXPECT_EQ(h.counts, (std::vector<double>{2, 0, 2, 2}));
  EXPECT_EQ(h.total(), 9.0);
  EXPECT_DOUBLE_EQ(h.pdf()[0], 2.0 / (9.0 * 0.5));
  EXPECT_EQ(h.edges().front(), -1.0);
  EXPECT_EQ(h.edges().back(), 1.0);
}

TEST(ForceAngle, ConventionsOfFigure15) {
  EXPECT_DOUBLE_EQ(force_angle_degrees(1.0, 0.0), 0.0);
  EXPECT_DOUBLE_EQ(force_angle_degrees(-1.0, 0.0), 180.0);
  EXPECT_NEAR(force_angle_degrees(1.0, std::sqrt(3.0)), 60.0, 1e-12);
  EXPECT_NEAR(force_angle_degrees(-1.0, std::sqrt(3.0)), 120.0, 1e-12);
}

TEST(Rumpf, EquationEighteenForUniformDiameters) {
  // Diameters uniform in [a/2, a]: <d> = 3a/4, <d^2> = 7a^2/12, so eq. (17) is eq. (18).
  const double a = 2e-3, P = 3.0, z = 3.1, phi = 0.72;
  EXPECT_NEAR(rumpf_mean_force(P, z, phi, 0.75 * a, 7.0 / 12.0 * a * a),
              7.0 * std::numbers::pi * a / 9.0 * P / (z * phi), 1e-15);
  // Monodisperse spheres: [AR] eq. (22), <N> = pi a^2 P / (z Phi).
  EXPECT_NEAR(rumpf_mean_force(P, 6.0, 0.637, a, a * a * a),
              std::numbers::pi * a * a * P / (6.0 * 0.637), 1e-15);
}

} // namespace
} // namespace granpack
