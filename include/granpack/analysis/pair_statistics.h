#pragma once
// Pair statistics of [AR] sec. III D and IV C (docs/analysis-statistics.md): the pair
// correlation function g(r) (fig. 5, 8), the gap-dependent coordination number z(h) (fig. 6,
// 9-12) and the power-law fit z(h) = z(0) + A h^beta of eq. (35).
//
// Distributed use (MPI-free here; the driver reduces). The accumulators take the pairs the
// driver gives, every unordered pair {i, j} exactly once over all ranks (e.g. on the rank
// owning the grain with the smaller global id, as the Verlet list does), with weight 1. The
// alternative "each owned i with every j != i" sees each pair twice: pass weight 1/2 then.
// Which grains take part (rattlers as simulated, fixed on the backbone, or removed: g^I, g^II,
// g^III and z^I, z^II, z^III) is the driver's choice of pairs and of n. The counts are a flat
// array of sums, all-reduced elementwise (MPI_SUM) in place; finish() then needs the global
// grain count n (and the cell volume for g).
#include <optional>
#include <vector>

namespace granpack {

/// g(r) on bins of width dr on [0, r_max] (r in units of a), normalised by the ideal-gas
/// count: for n grains in volume Omega, the expected number of unordered pairs in a shell is
/// n(n-1)/2 * V_shell / Omega (exact for independent uniform points while r_max < L_min/2).
template <int dim> class PairCorrelation {
public:
  /// r_max and bin_width in units of `diameter`; the last bin is cut at r_max.
  PairCorrelation(double diameter, double r_max, double bin_width);

  /// One pair at centre distance r (real units); pairs beyond r_max are ignored.
  void add(double r, double weight = 1.0);
  void merge(const PairCorrelation& other);

  /// Pair counts per bin: all-reduce in place (MPI_SUM) across ranks.
  std::vector<double>& sums() { return counts_; }
  const std::vector<double>& sums() const { return counts_; }

  struct Result {
    std::vector<double> r_lo, r_hi; ///< bin edges / a
    std::vector<double> count;      ///< pairs in the bin
    std::vector<double> ideal;      ///< ideal-gas expectation n(n-1)/2 V_shell/Omega
    std::vector<double> g;          ///< count / ideal
    std::vector<double> sigma;      ///< Poisson error of g: sqrt(max(count, 1)) / ideal
  };
  /// n: grains taking part; volume: Omega (area in 2D), real units.
  Result finish(double n_grains, double volume) const;

private:
  double a_, r_max_, dr_;
  std::vector<double> counts_;
};

/// z(h): mean number of neighbours per grain with gap r - (R_i + R_j) <= h, on a grid of h
/// (in units of a). z(h_k) = 2 C_k / n, C_k the number of pairs with gap <= h_k a.
class GapCoordination {
public:
  /// `h_grid` ascending, in units of `diameter`.
  GapCoordination(double diameter, std::vector<double> h_grid);

  /// The default grid: h = 0, then `points` values log-spaced from h_min to h_max (units of a).
  static std::vector<double> log_grid(double h_min = 1e-6, double h_max = 0.5, int points = 60,
                                      bool include_zero = true);

  /// One pair with gap r - R_i - R_j (real units; negative for an overlap).
  void add(double gap, double weight = 1.0);
  void merge(const GapCoordination& other);

  /// Pairs per grid interval: sums()[k] = pairs with h_{k-1} < gap/a <= h_k (k = 0: gap/a <=
  /// h_0). All-reduce in place (MPI_SUM); finish() accumulates them.
  std::vector<double>& sums() { return counts_; }
  const std::vector<double>& sums() const { return counts_; }
  const std::vector<double>& h_grid() const { return h_; }

  /// z(h_k) for every grid point; n: grains taking part.
  std::vector<double> finish(double n_grains) const;

private:
  double a_;
  std::vector<double> h_;
  std::vector<double> counts_;
};

/// Fit of eq. (35), z(h) = z0 + A h^beta, on the grid points with h_min <= h <= h_max.
struct PowerLawFitOptions {
  /// Fitting range in units of a. Default: the range where [AR] sec. IV C sees the power law
  /// in all states (above the elastic deflections, ~ 20/kappa; below 0.04 a, where z(h) of
  /// states C and D leaves it).
  double h_min = 1e-4, h_max = 0.04;
  /// z0 imposed (e.g. z from the contact count, or z^II(0) of eq. 36) instead of fitted.
  std::optional<double> fixed_z0;
  /// Exponents searched.
  double beta_min = 0.02, beta_max = 3.0;
};

struct PowerLawFit {
  double z0 = 0, amplitude = 0, exponent = 0; ///< z0, A, beta (h in units of a)
  /// One-standard-deviation errors from the covariance at the optimum (0 for a fixed z0).
  double z0_error = 0, amplitude_error = 0, exponent_error = 0;
  double rms_residual = 0; ///< sqrt(mean squared (weighted) residual)
  int points = 0;          ///< grid points in the range
};

/// Least squares over the points in range, weighted by 1/sigma_k^2 when `sigma` is given
/// (else unweighted). Variable projection: for a given beta the model is linear in (z0, A), so
/// the residual is minimised over beta alone (a scan of 400 log-spaced values of
/// [beta_min, beta_max], then a golden-section search around the best one), z0 and A following
/// by linear least squares. Errors: C = s^2 (J^T W J)^{-1} with J the Jacobian in (z0, A,
/// beta) and s^2 the reduced chi^2 (1 when sigma is given). Throws when fewer points than
/// parameters + 1 are in range.
PowerLawFit fit_gap_coordination(const std::vector<double>& h, const std::vector<double>& z,
                                 const PowerLawFitOptions& options = {},
                                 const std::vector<double>* sigma = nullptr);

} // namespace granpack
