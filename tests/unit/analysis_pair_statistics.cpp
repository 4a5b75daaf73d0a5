#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "granpack/analysis/pair_statistics.h"
#include "granpack/core/cell.h"
#include "granpack/core/error.h"
#include "lattice_fixtures.h"

using namespace granpack;

namespace {

/// n independent uniform points in a periodic cube (square) of side L, scaled positions.
template <int dim> std::vector<Vec<dim>> ideal_gas(int n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Vec<dim>> s(static_cast<std::size_t>(n));
  for (auto& x : s)
    for (int k = 0; k < dim; ++k)
      x[k] = u(rng);
  return s;
}

/// Every unordered pair once (brute force, minimum image), calling f(r).
template <int dim, class F>
void for_each_pair(const Cell<dim>& cell, const std::vector<Vec<dim>>& s, F f) {
  for (std::size_t i = 0; i < s.size(); ++i)
    for (std::size_t j = i + 1; j < s.size(); ++j)
      f(cell.min_image(s[i], s[j]).norm());
}

template <int dim> void check_ideal_gas(int n, double side) {
  const double a = 1.0;
  Cell<dim> cell;
  cell.length = Vec<dim>::Constant(side);
  const auto s = ideal_gas<dim>(n, 20240611u + dim);
  PairCorrelation<dim> g(a, 3.0, 0.05);
  for_each_pair(cell, s, [&](double r) { g.add(r); });
  const auto res = g.finish(n, cell.volume());
  ASSERT_EQ(res.g.size(), 60u);
  int tested = 0;
  double chi2 = 0;
  for (std::size_t k = 0; k < res.g.size(); ++k) {
    if (res.r_lo[k] < 0.5 - 1e-12)
      continue;
    // Null hypothesis g = 1: Poisson count around the ideal expectation.
    const double sigma = 1.0 / std::sqrt(res.ideal[k]);
    EXPECT_NEAR(res.g[k], 1.0, 4 * sigma)
        << "r/a in [" << res.r_lo[k] << ", " << res.r_hi[k] << ")";
    EXPECT_NEAR(res.sigma[k], sigma, 0.2 * sigma);
    chi2 += std::pow((res.g[k] - 1) / sigma, 2);
    ++tested;
  }
  EXPECT_EQ(tested, 50);
  // chi^2 with 50 degrees of freedom: mean 50, standard deviation 10.
  EXPECT_LT(chi2, 50 + 4 * 10);
  EXPECT_GT(chi2, 50 - 4 * 10);
}

} // namespace

TEST(PairCorrelation, IdealGasIsOne3D) {
  check_ideal_gas<3>(4000, 10.0);
}
TEST(PairCorrelation, IdealGasIsOne2D) {
  check_ideal_gas<2>(3000, 40.0);
}

TEST(PairCorrelation, OrderedPairsWithHalfWeightAndRankSplitGiveTheSameCounts) {
  Cell<3> cell;
  cell.length = Vec<3>::Constant(6.0);
  const auto s = ideal_gas<3>(300, 7u);
  PairCorrelation<3> once(1.0, 2.5, 0.1), rank0(1.0, 2.5, 0.1), rank1(1.0, 2.5, 0.1);
  for_each_pair(cell, s, [&](double r) { once.add(r); });
  // "Rank" 0 owns the first half of the grains, rank 1 the rest; each pairs its owned grains
  // with every other grain (ordered pairs, weight 1/2).
  for (std::size_t i = 0; i < s.size(); ++i)
    for (std::size_t j = 0; j < s.size(); ++j)
      if (i != j)
        (i < 150 ? rank0 : rank1).add(cell.min_image(s[i], s[j]).norm(), 0.5);
  rank0.merge(rank1);
  for (std::size_t k = 0; k < once.sums().size(); ++k)
    EXPECT_DOUBLE_EQ(rank0.sums()[k], once.sums()[k]);
}

namespace {

/// Gaps r - 2R of every pair of a lattice of grains of radius R (brute force).
template <int dim>
GapCoordination lattice_gaps(const Cell<dim>& cell, const std::vector<Vec<dim>>& s, double radius) {
  GapCoordination z(2 * radius, GapCoordination::log_grid());
  for_each_pair(cell, s, [&](double r) { z.add(r - 2 * radius); });
  return z;
}

} // namespace

TEST(GapCoordination, FccAtContactHas12NeighboursUpToTheSecondShell) {
  // FCC, nearest-neighbour distance 1, 4 x 4 x 4 cubic cells of side sqrt(2), 256 grains of
  // diameter a = 1 + 1e-9 (overlap 1e-9: at contact). Second shell at r = sqrt(2) a.
  const double c = std::sqrt(2.0);
  const int cells = 4;
  Cell<3> cell;
  cell.length = Vec<3>::Constant(cells * c);
  std::vector<Vec<3>> s;
  const double basis[4][3] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
  for (int x = 0; x < cells; ++x)
    for (int y = 0; y < cells; ++y)
      for (int zc = 0; zc < cells; ++zc)
        for (const auto& b : basis)
          s.push_back(Vec<3>(x + b[0], y + b[1], zc + b[2]) / cells);
  const double radius = 0.5 * (1 + 1e-9);
  const auto acc = lattice_gaps(cell, s, radius);
  const auto z = acc.finish(double(s.size()));
  const auto& h = acc.h_grid();
  ASSERT_EQ(h.size(), 61u);
  EXPECT_EQ(h.front(), 0.0);
  EXPECT_NEAR(h[1], 1e-6, 1e-18);
  EXPECT_DOUBLE_EQ(h.back(), 0.5);
  const double second_shell = (std::sqrt(2.0) - 2 * radius) / (2 * radius); // 0.41421 a
  for (std::size_t k = 0; k < h.size(); ++k)
    EXPECT_DOUBLE_EQ(z[k], h[k] < second_shell ? 12.0 : 18.0) << "h/a = " << h[k];
}

TEST(GapCoordination, TriangularLatticeHas6NeighboursOnTheWholeGrid) {
  // 2D: triangular lattice, rectangular cell (1, sqrt 3) with 2 grains, 6 x 4 cells; the
  // second shell (sqrt 3) lies beyond the grid's 0.5 a.
  const int nx = 6, ny = 4;
  Cell<2> cell;
  const std::vector<Vec<2>> s = test::triangular_lattice(nx, ny, cell);
  const auto z = lattice_gaps(cell, s, 0.5 * (1 + 1e-9)).finish(double(s.size()));
  for (double v : z)
    EXPECT_DOUBLE_EQ(v, 6.0);
}

namespace {
std::vector<double> power_law(const std::vector<double>& h, double z0, double a, double beta) {
  std::vector<double> z;
  for (double x : h)
    z.push_back(z0 + a * std::pow(x, beta));
  return z;
}
} // namespace

TEST(GapCoordinationFit, RecoversNoiseFreeParameters) {
  const auto h = GapCoordination::log_grid();
  for (double beta : {0.35, 0.55, 1.3}) {
    auto z = power_law(h, 4.5, 2.0, beta);
    // Points outside the default range [1e-4, 0.04] must not matter.
    for (std::size_t k = 0; k < h.size(); ++k)
      if (h[k] < 1e-4 || h[k] > 0.04)
        z[k] = 1e3;
    const auto fit = fit_gap_coordination(h, z);
    EXPECT_EQ(fit.points, 27);
    EXPECT_NEAR(fit.z0, 4.5, 1e-6) << "beta " << beta;
    EXPECT_NEAR(fit.amplitude, 2.0, 1e-6) << "beta " << beta;
    EXPECT_NEAR(fit.exponent, beta, 1e-6);
    EXPECT_LT(fit.rms_residual, 1e-9);
    // z0 imposed.
    PowerLawFitOptions opt;
    opt.fixed_z0 = 4.5;
    const auto fixed = fit_gap_coordination(h, z, opt);
    EXPECT_EQ(fixed.z0, 4.5);
    EXPECT_NEAR(fixed.amplitude, 2.0, 1e-6);
    EXPECT_NEAR(fixed.exponent, beta, 1e-6);
  }
}

TEST(GapCoordinationFit, NoisyDataWithinFourStandardErrors) {
  // z(h) = 4.5 + 2 h^0.55 with Gaussian noise of 0.002 on each point (a z(h) measured on
  // ~10^5 grains has Poisson errors of this order). Stated tolerance: each parameter within
  // 4 of its fitted standard errors, and the errors small: beta +- 0.02, z0 +- 0.01.
  const auto h = GapCoordination::log_grid();
  const double noise = 0.002;
  std::mt19937_64 rng(12345);
  std::normal_distribution<double> gauss(0.0, noise);
  auto z = power_law(h, 4.5, 2.0, 0.55);
  for (double& v : z)
    v += gauss(rng);
  const std::vector<double> sigma(h.size(), noise);
  for (const bool weighted : {false, true}) {
    const auto fit = fit_gap_coordination(h, z, {}, weighted ? &sigma : nullptr);
    EXPECT_NEAR(fit.z0, 4.5, 4 * fit.z0_error);
    EXPECT_NEAR(fit.amplitude, 2.0, 4 * fit.amplitude_error);
    EXPECT_NEAR(fit.exponent, 0.55, 4 * fit.exponent_error);
    EXPECT_LT(fit.exponent_error, 0.02);
    EXPECT_LT(fit.z0_error, 0.01);
    EXPECT_GT(fit.exponent_error, 0);
    // Unweighted: the rms of z - fit, about the noise; weighted: of (z - fit)/sigma, about 1.
    const double expected_rms = weighted ? 1.0 : noise;
    EXPECT_NEAR(fit.rms_residual, expected_rms, 0.3 * expected_rms);
    std::printf("  fit (%s): z0 %.5f +- %.5f, A %.4f +- %.4f, beta %.4f +- %.4f\n",
                weighted ? "weighted" : "unweighted", fit.z0, fit.z0_error, fit.amplitude,
                fit.amplitude_error, fit.exponent, fit.exponent_error);
  }
}

TEST(GapCoordinationFit, RefusesTooFewPoints) {
  const std::vector<double> h = {1e-3, 1e-2, 0.1}, z = {1, 2, 3};
  EXPECT_THROW(fit_gap_coordination(h, z), Error);
}
