// Density fluctuations of 2D packings (include/granpack/analysis/density_correlation.h):
// the rasterised area is the disks' area; I(k) of one disk is its analytic form factor
// |2 pi R J1(kR)/k|^2 / A; the closed form used for eq. (28) equals the paper's
// hypergeometric series where that converges and the Hankel integral of eq. (27) elsewhere;
// the fit recovers d_F and xi from a curve made by eq. (28), and eq. (27)'s real-space fit from
// a curve made by eq. (27); a curve without cut-off leaves xi undetermined (no number with a
// zero error) and the regime condition takes the errors into account; C(r) of one disk is the
// overlap area of two disks; holes of known shape give eq. (29)'s radius and wrapping holes are
// recognised.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "granpack/analysis/density_correlation.h"

namespace granpack {
namespace {

/// One disk of radius R at `centre` in the 20 x 20 periodic cell, on n x n nodes.
std::vector<std::uint8_t> one_disk(const Vec<2>& centre, double R, int n) {
  const std::vector<Disk> d = {{centre, R}};
  return rasterize_disks(d, Vec<2>(20.0, 20.0), n, n);
}

TEST(DensityCorrelation, RasterisedAreaIsTheDiskArea) {
  const Vec<2> L(10.0, 8.0);
  // One disk across the corner of the cell (its four quarters in four corners).
  std::vector<Disk> d = {{Vec<2>(0.1, 7.9), 1.3}, {Vec<2>(5.0, 4.0), 0.7}};
  const int nx = 2000, ny = 1600;
  const auto chi = rasterize_disks(d, L, nx, ny);
  double nodes = 0;
  for (auto c : chi)
    nodes += c;
  const double area = nodes * (L[0] / nx) * (L[1] / ny);
  EXPECT_NEAR(area, std::numbers::pi * (1.3 * 1.3 + 0.7 * 0.7), 2e-3);
}

TEST(DensityCorrelation, SingleDiskGivesItsFormFactor) {
  const Vec<2> L(20.0, 20.0);
  const double R = 1.5;
  const int n = 1024;
  const auto chi = one_disk(Vec<2>(7.3, 11.1), R, n);
  const auto c = scattering_function(chi, L, n, n, 6.0, 30);
  ASSERT_GT(c.k.size(), 10u);
  // |chi^(k)| depends only on |k| for one disk: the bin mean is the form factor at the bin's k
  // up to its variation across the bin; compare where it is flat (kR < 1).
  for (std::size_t b = 0; b < c.k.size(); ++b) {
    const double k = c.k[b];
    if (k * R > 1.0)
      continue;
    const double f = 2 * std::numbers::pi * R * std::cyl_bessel_j(1.0, k * R) / k;
    EXPECT_NEAR(c.I[b], f * f / (L[0] * L[1]), 0.02 * f * f / (L[0] * L[1])) << "k = " << k;
  }
}

TEST(DensityCorrelation, ClosedFormMatchesHypergeometricSeriesAndHankelIntegral) {
  for (double d : {1.5, 1.93}) {
    const double xi = 6.0;
    // Paper's form (eq. 28 without Cst, amplitude Phi l^(2-d) = 1): 2 pi Gamma(d) xi^d 2F1(...).
    for (double k : {0.01, 0.05, 0.1}) { // xi k < 1: the 2F1 series converges
      const double z = -xi * xi * k * k, a = (1 + d) / 2, b = d / 2;
      double term = 1, sum = 1;
      for (int n = 0; n < 400; ++n) {
        term *= (a + n) * (b + n) / ((1.0 + n) * (n + 1)) * z;
        sum += term;
      }
      const double paper = 2 * std::numbers::pi * std::tgamma(d) * std::pow(xi, d) * sum;
      EXPECT_NEAR(fractal_blob_intensity(k, d, xi, 1.0), paper, 1e-9 * paper);
    }
    // Any k: 2 pi int r^(d-1) e^(-r/xi) J0(kr) dr by the trapezoidal rule on a fine grid.
    for (double k : {0.5, 2.0}) {
      double s = 0;
      const double h = 1e-3;
      for (int i = 1; i < 200000; ++i) {
        const double r = i * h;
        s += std::pow(r, d - 1) * std::exp(-r / xi) * std::cyl_bessel_j(0.0, k * r) * h;
      }
      const double hankel = 2 * std::numbers::pi * s;
      EXPECT_NEAR(fractal_blob_intensity(k, d, xi, 1.0), hankel, 2e-3 * std::abs(hankel) + 1e-6);
    }
  }
  EXPECT_NEAR(legendre_p(2.0, 0.3), 0.5 * (3 * 0.09 - 1), 1e-14); // P_2 is a polynomial
}

TEST(DensityCorrelation, FitRecoversFractalDimensionAndBlobSize) {
  ScatteringCurve c;
  const double d = 1.6, xi = 7.0, amp = 0.4, cst = 0.02;
  for (int i = 0; i < 40; ++i) {
    const double k = 0.1 * std::pow(60.0, i / 39.0);
    c.k.push_back(k);
    c.I.push_back(cst + fractal_blob_intensity(k, d, xi, amp));
    c.I_error.push_back(0);
    c.count.push_back(1);
  }
  const FractalFit f = fit_fractal_blob(c, 0.1, 6.0, 0.4);
  ASSERT_EQ(f.points, 40);
  EXPECT_NEAR(f.d_f, d, 1e-4);
  EXPECT_NEAR(f.xi, xi, 1e-3);
  EXPECT_NEAR(f.constant, cst, 1e-5);
  EXPECT_LT(f.rms_log_residual, 1e-6);
}

TEST(DensityCorrelation, FitWithoutCutOffIsUndetermined) {
  // A pure power law plus a constant: xi runs away (the case that reported xi ~ 1e11-1e15 with
  // an error of 0): undetermined, with a reason, and never a fractal regime.
  ScatteringCurve c;
  for (int i = 0; i < 40; ++i) {
    const double k = 0.05 * std::pow(120.0, i / 39.0);
    c.k.push_back(k);
    c.I.push_back(0.01 + 0.3 * std::pow(k, -1.6));
    c.I_error.push_back(0);
    c.count.push_back(4 + i * i);
  }
  const FractalFit f = fit_fractal_blob(c, 0.05, 6.0, 0.3, 125.0);
  EXPECT_FALSE(f.determined) << "xi = " << f.xi << " +- " << f.xi_error;
  EXPECT_FALSE(f.reason.empty());
  EXPECT_FALSE(fractal_regime_failure(f, 1.0, 125.0).empty());
}

TEST(DensityCorrelation, RegimeConditionUsesTheErrors) {
  FractalFit f;
  f.determined = true, f.points = 30, f.d_f = 1.5, f.d_f_error = 0.05, f.xi = 53, f.xi_error = 120;
  EXPECT_EQ(fractal_regime_failure(f, 1.0, 200.0), "xi - 2 sigma_xi <= a"); // 53 +- 120: no regime
  f.xi_error = 5;
  EXPECT_EQ(fractal_regime_failure(f, 1.0, 200.0), "");
  EXPECT_EQ(fractal_regime_failure(f, 1.0, 120.0), "xi + 2 sigma_xi >= L/2");
  f.d_f = 1.95, f.d_f_error = 0.1;
  EXPECT_EQ(fractal_regime_failure(f, 1.0, 200.0), "d_F + 2 sigma_dF >= 2.1");
  f.d_f = 1.5, f.d_f_error = std::nan("");
  EXPECT_EQ(fractal_regime_failure(f, 1.0, 200.0), "sigma_dF >= 0.2");
  f.determined = false, f.reason = "singular covariance";
  EXPECT_EQ(fractal_regime_failure(f, 1.0, 200.0), "fit undetermined: singular covariance");
}

TEST(DensityCorrelation, RealSpaceFitRecoversEq27) {
  CorrelationCurve c;
  const double d = 1.55, xi = 6.0, phi = 0.2, l = 0.4;
  for (int i = 1; i < 200; ++i) {
    const double r = 0.25 * i;
    c.r.push_back(r);
    c.C.push_back(phi * std::pow(r / l, d - 2) * std::exp(-r / xi));
    c.count.push_back(1);
  }
  const FractalFit f = fit_fractal_real_space(c, 1.0, 40.0, phi);
  ASSERT_TRUE(f.determined) << f.reason;
  EXPECT_NEAR(f.d_f, d, 1e-9);
  EXPECT_NEAR(f.xi, xi, 1e-8);
  EXPECT_NEAR(f.length_l, l, 1e-8);
  EXPECT_NEAR(f.lo, 1.0, 1e-12);
  EXPECT_NEAR(f.hi, 40.0, 1e-12);
  // Without a cut-off (xi -> infinity) the fit says so instead of returning a number.
  for (std::size_t i = 0; i < c.r.size(); ++i)
    c.C[i] = phi * std::pow(c.r[i] / l, d - 2) * std::exp(c.r[i] / 500);
  const FractalFit g = fit_fractal_real_space(c, 1.0, 40.0, phi, 100.0);
  EXPECT_FALSE(g.determined);
  EXPECT_FALSE(g.reason.empty());
}

TEST(DensityCorrelation, CorrelationOfOneDiskIsTheOverlapArea) {
  const Vec<2> L(20.0, 20.0);
  const double R = 2.0;
  const int n = 1000;
  const auto chi = one_disk(Vec<2>(3.1, 17.6), R, n);
  double solid = 0;
  for (auto x : chi)
    solid += x;
  const double phi = solid / double(chi.size());
  const DensitySpectra s = density_spectra(chi, L, n, n, 5.0, 20, 10.0, 0.1);
  ASSERT_EQ(s.correlation.r.size(), 100u);
  for (std::size_t b = 0; b < s.correlation.r.size(); ++b) {
    const double r = s.correlation.r[b];
    // Two disks of radius R at distance r overlap on 2 R^2 acos(r/2R) - (r/2) sqrt(4R^2 - r^2).
    const double overlap =
        r < 2 * R ? 2 * R * R * std::acos(r / (2 * R)) - 0.5 * r * std::sqrt(4 * R * R - r * r)
                  : 0.0;
    EXPECT_NEAR(s.correlation.C[b], overlap / (L[0] * L[1]) - phi * phi, 1e-3 * phi) << "r = " << r;
  }
  // The scattering curve is the one scattering_function gives.
  const ScatteringCurve c = scattering_function(chi, L, n, n, 5.0, 20);
  ASSERT_EQ(c.I.size(), s.scattering.I.size());
  for (std::size_t b = 0; b < c.I.size(); ++b)
    EXPECT_EQ(c.I[b], s.scattering.I[b]);
}

TEST(DensityCorrelation, HolesAndTheirEquivalentRadii) {
  // Solid everywhere except a square hole of side s (radius of gyration: 2 <r^2> = s^2 / 3)
  // and a channel that wraps along y.
  const int nx = 400, ny = 300;
  const Vec<2> L(4.0, 3.0); // spacing 0.01
  std::vector<std::uint8_t> chi(std::size_t(nx) * ny, 1);
  for (int i = 100; i < 200; ++i)
    for (int j = 50; j < 150; ++j)
      chi[std::size_t(i) * ny + j] = 0;
  for (int i = 300; i < 310; ++i)
    for (int j = 0; j < ny; ++j)
      chi[std::size_t(i) * ny + j] = 0;
  // A second square hole split by the x boundary (columns 395..399 and 0..4: side 10 nodes).
  for (int i : {395, 396, 397, 398, 399, 0, 1, 2, 3, 4})
    for (int j = 200; j < 210; ++j)
      chi[std::size_t(i) * ny + j] = 0;
  const HoleStatistics h = hole_statistics(chi, L, nx, ny);
  EXPECT_EQ(h.holes, 3);
  EXPECT_EQ(h.wrapping_holes, 1);
  ASSERT_EQ(h.radii.size(), 2u);
  // A square of n x n nodes at spacing e: 2 <r^2> = 2 * 2 * e^2 (n^2 - 1) / 12.
  auto square = [](int n, double e) { return std::sqrt(4 * e * e * (n * n - 1) / 12.0); };
  // In scan order: the small square (it starts at column 0) first, unwrapped across x = 0.
  EXPECT_NEAR(h.radii[0], square(10, 0.01), 1e-12);
  EXPECT_NEAR(h.radii[1], square(100, 0.01), 1e-12);
  EXPECT_NEAR(h.weighted_mean_radius,
              (1e4 * square(100, 0.01) + 100 * square(10, 0.01)) / (1e4 + 100), 1e-12);
}

TEST(DensityCorrelation, PooledCurveCountsEveryWaveVectorOnce) {
  // Two samples on the same bins: the pooled bin is the count-weighted mean. A third whose cell
  // is 3 % larger puts its points in the bins holding their k.
  ScatteringCurve a{{1.0, 2.0, 4.0}, {10.0, 5.0, 1.0}, {1.0, 0.5, 0.1}, {4, 8, 16}};
  ScatteringCurve b{{1.0, 2.0, 4.0}, {20.0, 3.0, 3.0}, {2.0, 0.3, 0.2}, {4, 8, 16}};
  ScatteringCurve c{{0.97, 1.94}, {6.0, 7.0}, {1.0, 1.0}, {2, 8}};
  const std::vector<ScatteringCurve> curves = {a, b, c};
  const ScatteringCurve p = pooled_scattering(curves);
  ASSERT_EQ(p.k.size(), 3u);
  EXPECT_DOUBLE_EQ(p.count[0], 10.0);
  EXPECT_DOUBLE_EQ(p.I[0], (4 * 10.0 + 4 * 20.0 + 2 * 6.0) / 10.0);
  EXPECT_DOUBLE_EQ(p.k[0], (4 * 1.0 + 4 * 1.0 + 2 * 0.97) / 10.0);
  EXPECT_DOUBLE_EQ(p.I[1], (8 * 5.0 + 8 * 3.0 + 8 * 7.0) / 24.0);
  EXPECT_DOUBLE_EQ(p.I[2], 2.0);
  EXPECT_DOUBLE_EQ(p.I_error[2], std::hypot(16 * 0.1, 16 * 0.2) / 32.0);
  // One sample pools to itself.
  const std::vector<ScatteringCurve> one = {a};
  const ScatteringCurve q = pooled_scattering(one);
  EXPECT_EQ(q.I, a.I);
  EXPECT_EQ(q.k, a.k);
  EXPECT_TRUE(pooled_scattering({}).k.empty());
}

} // namespace
} // namespace granpack

TEST(DensityCorrelation, FftFriendlySizesHaveOnlyTheFactors2357) {
  EXPECT_EQ(granpack::fft_friendly_size(1), 1);
  EXPECT_EQ(granpack::fft_friendly_size(7), 7);
  EXPECT_EQ(granpack::fft_friendly_size(11), 12);
  EXPECT_EQ(granpack::fft_friendly_size(307), 315);   // 3^2 x 5 x 7
  EXPECT_EQ(granpack::fft_friendly_size(3070), 3072); // 2^10 x 3
  // Never more than a few percent above n where meshes are large.
  for (int n = 1000; n < 20000; n += 37) {
    const int m = granpack::fft_friendly_size(n);
    EXPECT_GE(m, n);
    EXPECT_LE(m, n + n / 20) << n;
  }
}
