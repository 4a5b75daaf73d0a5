// Translational order rho_k (include/granpack/analysis/translational_order.h): a lattice has
// rho_k = 1 on its reciprocal vectors and is found by the peak search; a lattice shifted or
// thermally displaced by a known Gaussian keeps the Debye-Waller value exp(-k^2 s^2 / 2);
// uncorrelated positions give rho_k ~ 1/sqrt(N).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "granpack/analysis/translational_order.h"

namespace granpack {
namespace {

std::vector<Vec<3>> fcc(int c, double l) {
  std::vector<Vec<3>> x;
  const double basis[4][3] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
  for (int i = 0; i < c; ++i)
    for (int j = 0; j < c; ++j)
      for (int k = 0; k < c; ++k)
        for (const auto& b : basis)
          x.push_back(Vec<3>(l * (i + b[0]), l * (j + b[1]), l * (k + b[2])));
  return x;
}

TEST(TranslationalOrder, FccHasUnitPeaksAtTheReciprocalVectors) {
  const int c = 6;
  const double l = 1.7;
  auto x = fcc(c, l);
  const Vec<3> L = Vec<3>::Constant(c * l);
  EXPECT_NEAR(translational_order<3>(x, L, {c, c, c}), 1.0, 1e-12);     // (111)
  EXPECT_NEAR(translational_order<3>(x, L, {2 * c, 0, 0}), 1.0, 1e-12); // (200)
  EXPECT_LT(translational_order<3>(x, L, {c, 0, 0}), 1e-12);            // (100): extinct in FCC
  // A rigid shift changes only the phase.
  for (auto& p : x)
    p += Vec<3>(0.31, -0.2, 0.05);
  EXPECT_NEAR(translational_order<3>(x, L, {c, -c, c}), 1.0, 1e-12);
}

TEST(TranslationalOrder, PeakSearchFindsTheFirstShellOfFcc) {
  const int c = 5;
  const auto x = fcc(c, 1.6);
  const Vec<3> L = Vec<3>::Constant(c * 1.6);
  // N = 500, index bound ceil(500^(1/3)) = 8 >= c: the 4 (111) vectors (half space) and no (200).
  const auto peaks = find_bragg_peaks<3>(x, L, 8, 0.5);
  ASSERT_EQ(peaks.m.size(), 4u);
  for (const auto& m : peaks.m)
    for (int a = 0; a < 3; ++a)
      EXPECT_EQ(std::abs(m[a]), c);
  EXPECT_NEAR(mean_translational_order<3>(x, L, peaks), 1.0, 1e-12);
}

TEST(TranslationalOrder, GaussianDisplacementsGiveTheDebyeWallerFactor) {
  const int c = 12;
  const double l = 1.7, s = 0.1;
  auto x = fcc(c, l);
  const Vec<3> L = Vec<3>::Constant(c * l);
  std::mt19937_64 rng(7);
  std::normal_distribution<double> g(0.0, s);
  for (auto& p : x)
    p += Vec<3>(g(rng), g(rng), g(rng));
  const double k2 = 3 * std::pow(2 * std::numbers::pi / l, 2);
  const double expected = std::exp(-0.5 * k2 * s * s); // 0.505
  // Statistical error of the mean of N unit phasors: about 1/sqrt(N) = 0.0072 (N = 6912).
  EXPECT_NEAR(translational_order<3>(x, L, {c, c, c}), expected, 4.0 / std::sqrt(x.size()));
}

TEST(TranslationalOrder, UncorrelatedPositionsAreOfOrderOneOverRootN) {
  const int n = 4000;
  const Vec<3> L = Vec<3>::Constant(16.0);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.0, 16.0);
  std::vector<Vec<3>> x(n);
  for (auto& p : x)
    p = Vec<3>(u(rng), u(rng), u(rng));
  BraggPeaks<3> peaks;
  for (int i = 1; i <= 8; ++i)
    peaks.m.push_back({i, i, -i});
  // Mean of 8 values of |sum|/N, each Rayleigh with mean sqrt(pi / (4 N)) = 0.0140, sd 0.0073.
  const double r = mean_translational_order<3>(x, L, peaks);
  EXPECT_GT(r, 0.0140 - 4 * 0.0073 / std::sqrt(8.0));
  EXPECT_LT(r, 0.0140 + 4 * 0.0073 / std::sqrt(8.0));
  EXPECT_TRUE(find_bragg_peaks<3>(x, L, 6, 0.5).m.empty());
}

TEST(TranslationalOrder, TwoDimensionalSquareLattice) {
  std::vector<Vec<2>> x;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j)
      x.push_back(Vec<2>(i * 1.1, j * 1.1));
  const Vec<2> L = Vec<2>::Constant(11.0);
  const auto peaks = find_bragg_peaks<2>(x, L, 10, 0.5);
  // Half space of {(10,0),(0,10),(10,+-10)} and their negatives: (10,0), (10,10), (10,-10), (0,10).
  EXPECT_EQ(peaks.m.size(), 4u);
}

} // namespace
} // namespace granpack
