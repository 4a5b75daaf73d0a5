#include "granpack/analysis/pair_statistics.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "granpack/core/error.h"

namespace granpack {

// ---------------------------------------------------------------------------------------------
// g(r)

template <int dim>
PairCorrelation<dim>::PairCorrelation(double diameter, double r_max, double bin_width)
    : a_(diameter), r_max_(r_max), dr_(bin_width) {
  GRANPACK_CHECK(diameter > 0 && r_max > 0 && bin_width > 0 && bin_width <= r_max,
                 "PairCorrelation: need diameter, r_max >= bin_width > 0 (got "
                     << diameter << ", " << r_max << ", " << bin_width << ")");
  // Bins [k dr, (k+1) dr), the last one cut at r_max (tolerating round-off in r_max / dr).
  const auto nb = static_cast<std::size_t>(std::ceil(r_max / bin_width - 1e-9));
  counts_.assign(std::max<std::size_t>(nb, 1), 0.0);
}

template <int dim> void PairCorrelation<dim>::add(double r, double weight) {
  const double x = r / a_;
  if (!(x >= 0 && x < r_max_))
    return;
  const auto k = std::min(counts_.size() - 1, static_cast<std::size_t>(x / dr_));
  counts_[k] += weight;
}

template <int dim> void PairCorrelation<dim>::merge(const PairCorrelation& other) {
  GRANPACK_CHECK(other.counts_.size() == counts_.size() && other.dr_ == dr_ && other.a_ == a_,
                 "PairCorrelation::merge: different bins");
  for (std::size_t k = 0; k < counts_.size(); ++k)
    counts_[k] += other.counts_[k];
}

template <int dim>
typename PairCorrelation<dim>::Result PairCorrelation<dim>::finish(double n_grains,
                                                                   double volume) const {
  GRANPACK_CHECK(volume > 0, "PairCorrelation::finish: volume must be > 0");
  Result res;
  const double pairs = 0.5 * n_grains * (n_grains - 1);
  // Volume of the ball of radius x a: (4 pi / 3) (x a)^3 in 3D, pi (x a)^2 in 2D.
  auto ball = [&](double x) {
    const double r = x * a_;
    return dim == 3 ? 4.0 / 3.0 * std::numbers::pi * r * r * r : std::numbers::pi * r * r;
  };
  for (std::size_t k = 0; k < counts_.size(); ++k) {
    const double lo = static_cast<double>(k) * dr_;
    const double hi = std::min(lo + dr_, r_max_);
    const double ideal = pairs * (ball(hi) - ball(lo)) / volume;
    res.r_lo.push_back(lo);
    res.r_hi.push_back(hi);
    res.count.push_back(counts_[k]);
    res.ideal.push_back(ideal);
    res.g.push_back(counts_[k] / ideal);
    res.sigma.push_back(std::sqrt(std::max(counts_[k], 1.0)) / ideal);
  }
  return res;
}

// ---------------------------------------------------------------------------------------------
// z(h)

GapCoordination::GapCoordination(double diameter, std::vector<double> h_grid)
    : a_(diameter), h_(std::move(h_grid)), counts_(h_.size(), 0.0) {
  GRANPACK_CHECK(diameter > 0 && !h_.empty() && std::is_sorted(h_.begin(), h_.end()),
                 "GapCoordination: need diameter > 0 and a non-empty ascending h grid");
}

std::vector<double> GapCoordination::log_grid(double h_min, double h_max, int points,
                                              bool include_zero) {
  GRANPACK_CHECK(h_min > 0 && h_max > h_min && points >= 2,
                 "GapCoordination::log_grid: need 0 < h_min < h_max and points >= 2");
  std::vector<double> h;
  if (include_zero)
    h.push_back(0.0);
  const double ratio = std::log(h_max / h_min);
  for (int k = 0; k < points; ++k)
    h.push_back(h_min * std::exp(ratio * k / (points - 1)));
  h.back() = h_max;
  return h;
}

void GapCoordination::add(double gap, double weight) {
  const double x = gap / a_;
  // First grid point with h_k >= x: the pair counts for every k from there on.
  const auto k = static_cast<std::size_t>(std::lower_bound(h_.begin(), h_.end(), x) - h_.begin());
  if (k < counts_.size())
    counts_[k] += weight;
}

void GapCoordination::merge(const GapCoordination& other) {
  GRANPACK_CHECK(other.h_ == h_ && other.a_ == a_, "GapCoordination::merge: different grids");
  for (std::size_t k = 0; k < counts_.size(); ++k)
    counts_[k] += other.counts_[k];
}

std::vector<double> GapCoordination::finish(double n_grains) const {
  GRANPACK_CHECK(n_grains > 0, "GapCoordination::finish: need n > 0");
  std::vector<double> z(counts_.size());
  double cumulated = 0;
  for (std::size_t k = 0; k < counts_.size(); ++k) {
    cumulated += counts_[k];
    z[k] = 2.0 * cumulated / n_grains; // each pair is a neighbour of both its grains
  }
  return z;
}

// ---------------------------------------------------------------------------------------------
// eq. (35) fit

namespace {

/// The points of the fit, with sqrt of their weights.
struct FitData {
  Eigen::VectorXd h, z, sw;
};

struct LinearSolution {
  double z0 = 0, amplitude = 0, chi2 = 0;
};

/// Best (z0, A) for a given beta (z0 fixed if given): weighted linear least squares by QR.
LinearSolution solve_linear(const FitData& d, double beta, const std::optional<double>& fixed) {
  const Eigen::Index m = d.h.size();
  const Eigen::VectorXd phi = d.h.array().pow(beta);
  LinearSolution s;
  if (fixed) {
    s.z0 = *fixed;
    const Eigen::VectorXd a = d.sw.cwiseProduct(phi);
    const Eigen::VectorXd b =
        d.sw.cwiseProduct(d.z.array().matrix() - Eigen::VectorXd::Constant(m, s.z0));
    s.amplitude = a.dot(b) / a.squaredNorm();
    s.chi2 = (b - s.amplitude * a).squaredNorm();
    return s;
  }
  Eigen::MatrixXd basis(m, 2);
  basis.col(0) = d.sw;
  basis.col(1) = d.sw.cwiseProduct(phi);
  const Eigen::VectorXd b = d.sw.cwiseProduct(d.z);
  const Eigen::Vector2d x = basis.colPivHouseholderQr().solve(b);
  s.z0 = x[0];
  s.amplitude = x[1];
  s.chi2 = (b - basis * x).squaredNorm();
  return s;
}

} // namespace

PowerLawFit fit_gap_coordination(const std::vector<double>& h, const std::vector<double>& z,
                                 const PowerLawFitOptions& opt, const std::vector<double>* sigma) {
  GRANPACK_CHECK(h.size() == z.size() && (!sigma || sigma->size() == h.size()),
                 "fit_gap_coordination: h, z (and sigma) must have the same size");
  GRANPACK_CHECK(opt.h_min > 0 && opt.h_max > opt.h_min && opt.beta_min > 0 &&
                     opt.beta_max > opt.beta_min,
                 "fit_gap_coordination: need 0 < h_min < h_max and 0 < beta_min < beta_max");
  std::vector<std::size_t> in;
  for (std::size_t k = 0; k < h.size(); ++k)
    if (h[k] >= opt.h_min && h[k] <= opt.h_max && (!sigma || (*sigma)[k] > 0))
      in.push_back(k);
  const int params = opt.fixed_z0 ? 2 : 3;
  const auto m = static_cast<Eigen::Index>(in.size());
  GRANPACK_CHECK(m > params, "fit_gap_coordination: " << m << " points in [" << opt.h_min << ", "
                                                      << opt.h_max << "], need at least "
                                                      << params + 1);
  FitData d{Eigen::VectorXd(m), Eigen::VectorXd(m), Eigen::VectorXd(m)};
  for (Eigen::Index i = 0; i < m; ++i) {
    const std::size_t k = in[static_cast<std::size_t>(i)];
    d.h[i] = h[k];
    d.z[i] = z[k];
    d.sw[i] = sigma ? 1.0 / (*sigma)[k] : 1.0;
  }

  // Scan beta (log-spaced), then golden-section search in the bracket around the best value.
  auto chi2 = [&](double beta) { return solve_linear(d, beta, opt.fixed_z0).chi2; };
  constexpr int kScan = 400;
  std::vector<double> betas(kScan);
  const double log_span = std::log(opt.beta_max / opt.beta_min);
  std::size_t best = 0;
  double best_chi2 = std::numeric_limits<double>::infinity();
  for (int k = 0; k < kScan; ++k) {
    const auto ks = static_cast<std::size_t>(k);
    betas[ks] = opt.beta_min * std::exp(log_span * k / (kScan - 1));
    const double c = chi2(betas[ks]);
    if (c < best_chi2)
      best_chi2 = c, best = ks;
  }
  double lo = betas[best == 0 ? 0 : best - 1];
  double hi = betas[std::min<std::size_t>(best + 1, kScan - 1)];
  const double inv_phi = (std::sqrt(5.0) - 1) / 2;
  double x1 = hi - inv_phi * (hi - lo), x2 = lo + inv_phi * (hi - lo);
  double f1 = chi2(x1), f2 = chi2(x2);
  for (int it = 0; it < 200 && hi - lo > 1e-13 * hi; ++it) {
    if (f1 < f2) {
      hi = x2, x2 = x1, f2 = f1;
      x1 = hi - inv_phi * (hi - lo), f1 = chi2(x1);
    } else {
      lo = x1, x1 = x2, f1 = f2;
      x2 = lo + inv_phi * (hi - lo), f2 = chi2(x2);
    }
  }
  double beta = 0.5 * (lo + hi);
  if (best_chi2 < chi2(beta))
    beta = betas[best]; // keep the scan's value if it is better

  const LinearSolution s = solve_linear(d, beta, opt.fixed_z0);
  PowerLawFit fit;
  fit.z0 = s.z0;
  fit.amplitude = s.amplitude;
  fit.exponent = beta;
  fit.points = static_cast<int>(m);
  fit.rms_residual = std::sqrt(s.chi2 / static_cast<double>(m));

  // Covariance from the weighted Jacobian of the residuals in (z0, A, beta).
  Eigen::MatrixXd jac(m, params);
  int col = 0;
  if (!opt.fixed_z0)
    jac.col(col++) = d.sw;
  const Eigen::ArrayXd phi = d.h.array().pow(beta);
  jac.col(col++) = (d.sw.array() * phi).matrix();
  jac.col(col) = (d.sw.array() * s.amplitude * phi * d.h.array().log()).matrix();
  const double s2 = sigma ? 1.0 : s.chi2 / static_cast<double>(m - params);
  const Eigen::MatrixXd jtj = jac.transpose() * jac;
  const Eigen::MatrixXd cov = s2 * jtj.ldlt().solve(Eigen::MatrixXd::Identity(params, params));
  col = 0;
  if (!opt.fixed_z0)
    fit.z0_error = std::sqrt(std::max(0.0, cov(col, col))), ++col;
  fit.amplitude_error = std::sqrt(std::max(0.0, cov(col, col)));
  ++col;
  fit.exponent_error = std::sqrt(std::max(0.0, cov(col, col)));
  return fit;
}

template class PairCorrelation<2>;
template class PairCorrelation<3>;

} // namespace granpack
