#pragma once
// Density fluctuations of 2D packings ([GRC] sec. V): the scattering function I(k) of the
// solid indicator chi(r), its fit by the fractal-blob form (eq. 27-28) giving d_F and xi, and
// the holes (connected regions of chi = 0) with their equivalent radii (eq. 29-30). MPI-free;
// `granpack analyze` calls it on rank 0 with the gathered disks.
//
// chi is sampled at the nodes of a regular periodic mesh (spacing about a/100, [GRC] V C),
// I(k) = |chi^(k)|^2 / A (eq. 25) from a 2D FFT (FFTW), averaged in bins of |k|. The k = 0
// term (the mean) is dropped: I(k) then is the transform of C(r) - Phi^2, and the inverse FFT
// of |chi^(k)|^2 gives C(r) - Phi^2 itself (eq. 24), averaged in bins of |r|.
//
// Eq. (28) is the Fourier transform of eq. (27), C(r) - Phi^2 = Phi (r/l)^(d_F-2) exp(-r/xi).
// Its hypergeometric function of -xi^2 k^2 is evaluated through the equivalent closed form
//   2 pi int_0^inf r^(d-1) e^(-r/xi) J0(kr) dr = 2 pi Gamma(d) (p^2+k^2)^(-d/2) P_(d-1)(p/s),
// p = 1/xi, s = sqrt(p^2 + k^2), P_nu the Legendre function, whose series
// 2F1(-nu, nu+1; 1; (1 - p/s)/2) converges for every k (argument below 1/2).
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "granpack/core/vec.h"

namespace granpack {

struct Disk {
  Vec<2> center; ///< real coordinates (any image)
  double radius = 0;
};

/// The smallest node count >= n whose prime factors are all 2, 3, 5 or 7, the sizes FFTW
/// transforms fastest: a side of 3070 nodes (2 x 5 x 307) takes 3x as long as one of 3072.
int fft_friendly_size(int n);

/// The solid indicator on an nx x ny periodic mesh of the cell [0, L1) x [0, L2): node (i, j)
/// at ((i + 1/2) L1/nx, (j + 1/2) L2/ny), 1 inside a disk. Row-major, index i * ny + j.
std::vector<std::uint8_t> rasterize_disks(std::span<const Disk> disks, const Vec<2>& L, int nx,
                                          int ny);

struct ScatteringCurve {
  std::vector<double> k;       ///< bin centres (mean |k| of the bin's wave vectors), 1/m
  std::vector<double> I;       ///< mean I(k) in the bin, m^2
  std::vector<double> I_error; ///< standard error of the bin mean
  std::vector<double> count;   ///< wave vectors in the bin
};

/// I(k) of a mesh, averaged in `bins` logarithmic |k| bins from 2 pi / max(L) to k_max.
ScatteringCurve scattering_function(const std::vector<std::uint8_t>& chi, const Vec<2>& L, int nx,
                                    int ny, double k_max, int bins);

/// The I(k) of several samples pooled as one curve ([GRC] fig. 23 averages samples before
/// fitting): the bins of the curve with the most points are the common bins (edges at the
/// geometric means of its neighbouring k), every sample's bin goes to the common bin holding its
/// k, and each common bin is the count-weighted mean of what it receives (every wave vector of
/// every sample counts once), with count the total and the error propagated from the samples'
/// bin errors. Samples whose cells differ by less than a bin width (2-7 % here) share bins
/// exactly; larger differences only shift a sample's points by up to half a bin. Empty input:
/// empty curve.
ScatteringCurve pooled_scattering(std::span<const ScatteringCurve> curves);

struct CorrelationCurve {
  std::vector<double> r;     ///< bin centres (mean |r| of the bin's mesh vectors), m
  std::vector<double> C;     ///< mean C(r) - Phi^2 in the bin (Phi of the mesh)
  std::vector<double> count; ///< mesh vectors in the bin
};

/// I(k) as scattering_function and C(r) - Phi^2 (eq. 24 by the inverse FFT of |chi^(k)|^2) in
/// linear |r| bins of width r_bin from 0 to r_max, from one forward FFT.
struct DensitySpectra {
  ScatteringCurve scattering;
  CorrelationCurve correlation;
};
DensitySpectra density_spectra(const std::vector<std::uint8_t>& chi, const Vec<2>& L, int nx,
                               int ny, double k_max, int bins, double r_max, double r_bin);

/// Eq. (28) without its constant: amplitude * Gamma(d) (p^2+k^2)^(-d/2) P_(d-1)(p/s) * 2 pi,
/// amplitude = Phi l^(2-d).
double fractal_blob_intensity(double k, double d_f, double xi, double amplitude);
/// Legendre function of the first kind P_nu(x), 0 <= x <= 1, by its hypergeometric series.
double legendre_p(double nu, double x);

struct FractalFit {
  double d_f = 0, xi = 0, amplitude = 0, constant = 0;
  double d_f_error = 0, xi_error = 0; ///< from the covariance of the fit (residual scaled)
  double length_l = 0;                ///< l of eq. (27) from amplitude = Phi l^(2-d)
  double rms_log_residual = 0;        ///< unweighted rms of the log residuals
  double lo = 0, hi = 0;              ///< the window actually fitted (k or r of its end points)
  int points = 0;
  bool converged = false; ///< the minimiser stopped at a minimum (not on its evaluation limit)
  /// d_F and xi are numbers with finite, non-zero errors: converged, a non-singular covariance,
  /// xi below the fit's xi_max. Otherwise `reason` says why and the values mean nothing.
  bool determined = false;
  std::string reason;
};

/// Least squares (Levenberg-Marquardt) of log I(k) by log(Cst + eq. 28) over the bins with
/// k in [k_lo, k_hi], each weighted by its count of wave vectors (the inverse variance of the
/// log of a mean of `count` exponentially distributed |chi^(k)|^2). Starting values from the
/// curve itself; Phi converts the amplitude to l. A xi beyond xi_max (the cell) or a singular
/// covariance leaves the fit undetermined.
FractalFit fit_fractal_blob(const ScatteringCurve& c, double k_lo, double k_hi, double phi,
                            double xi_max = std::numeric_limits<double>::infinity());

/// Eq. (27) in real space: weighted linear least squares of
///   ln(C - Phi^2) = ln(Phi l^(2-d)) + (d - 2) ln r - r / xi
/// over the bins with r in [r_lo, r_hi] up to the first bin where C - Phi^2 <= 0, each with
/// weight (C - Phi^2)^2 (the log fit then approximates a least-squares fit of C - Phi^2 itself,
/// so the noisy tail near zero does not dominate). Undetermined when xi comes out negative or
/// beyond xi_max, with fewer than 6 points or a singular covariance.
FractalFit fit_fractal_real_space(const CorrelationCurve& c, double r_lo, double r_hi, double phi,
                                  double xi_max = std::numeric_limits<double>::infinity());

/// The condition under which a fit describes a fractal regime (docs/analysis.md): determined,
/// at least 6 points, xi - 2 sigma_xi > a and xi + 2 sigma_xi < l_cell / 2 (l_cell the
/// smaller cell side), d_F - 2 sigma_dF > 1 and d_F + 2 sigma_dF < 2.1, 0 < sigma_dF < 0.2.
/// Returns an empty string when it holds, else the first condition that fails.
std::string fractal_regime_failure(const FractalFit& f, double a, double l_cell);

struct HoleStatistics {
  std::int64_t holes = 0;
  std::int64_t wrapping_holes = 0; ///< holes that wrap around the periodic cell (excluded)
  double weighted_mean_radius = 0; ///< <R>_w of eq. (30) over the non-wrapping holes, m
  double largest_radius = 0;
  std::vector<double> radii, nodes; ///< R_H (eq. 29) and N_H of every non-wrapping hole
};

/// Connected regions of chi = 0 (4-neighbour connectivity, periodic), their radius of gyration
/// radius R_H = sqrt(2 <|x - x_c|^2>) (eq. 29, coordinates unwrapped across the boundary).
HoleStatistics hole_statistics(const std::vector<std::uint8_t>& chi, const Vec<2>& L, int nx,
                               int ny);

} // namespace granpack
