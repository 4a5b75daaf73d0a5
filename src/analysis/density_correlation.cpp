#include "granpack/analysis/density_correlation.h"

#include <fftw3.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <numbers>
#include <unsupported/Eigen/NonLinearOptimization>
#include <unsupported/Eigen/NumericalDiff>

#include "granpack/core/error.h"

namespace granpack {

int fft_friendly_size(int n) {
  GRANPACK_CHECK(n > 0, "fft_friendly_size: need n > 0");
  for (int m = n;; ++m) {
    int r = m;
    for (int f : {2, 3, 5, 7})
      while (r % f == 0)
        r /= f;
    if (r == 1)
      return m;
  }
}

std::vector<std::uint8_t> rasterize_disks(std::span<const Disk> disks, const Vec<2>& L, int nx,
                                          int ny) {
  GRANPACK_CHECK(nx > 0 && ny > 0, "rasterize_disks: mesh must have nodes");
  std::vector<std::uint8_t> chi(std::size_t(nx) * std::size_t(ny), 0);
  const double dx = L[0] / nx, dy = L[1] / ny;
  for (const Disk& d : disks) {
    // Centre wrapped into the cell; the node loop wraps indices, so one image suffices.
    const double cx = d.center[0] - L[0] * std::floor(d.center[0] / L[0]);
    const double cy = d.center[1] - L[1] * std::floor(d.center[1] / L[1]);
    const int i0 = int(std::floor((cx - d.radius) / dx - 0.5)),
              i1 = int(std::ceil((cx + d.radius) / dx - 0.5));
    const int j0 = int(std::floor((cy - d.radius) / dy - 0.5)),
              j1 = int(std::ceil((cy + d.radius) / dy - 0.5));
    const double r2 = d.radius * d.radius;
    for (int i = i0; i <= i1; ++i) {
      const double x = (i + 0.5) * dx - cx;
      const int iw = ((i % nx) + nx) % nx;
      for (int j = j0; j <= j1; ++j) {
        const double y = (j + 0.5) * dy - cy;
        if (x * x + y * y < r2)
          chi[std::size_t(iw) * ny + std::size_t(((j % ny) + ny) % ny)] = 1;
      }
    }
  }
  return chi;
}

DensitySpectra density_spectra(const std::vector<std::uint8_t>& chi, const Vec<2>& L, int nx,
                               int ny, double k_max, int bins, double r_max, double r_bin) {
  GRANPACK_CHECK(chi.size() == std::size_t(nx) * std::size_t(ny), "scattering_function: mesh size");
  GRANPACK_CHECK(bins > 0 && k_max > 0, "scattering_function: need bins > 0 and k_max > 0");
  GRANPACK_CHECK(r_max <= 0 || r_bin > 0, "density_spectra: need r_bin > 0");
  const int nyc = ny / 2 + 1;
  double* in = fftw_alloc_real(std::size_t(nx) * ny);
  fftw_complex* out = fftw_alloc_complex(std::size_t(nx) * nyc);
  GRANPACK_CHECK(in && out,
                 "scattering_function: out of memory for a " << nx << " x " << ny << " FFT");
  fftw_plan plan = fftw_plan_dft_r2c_2d(nx, ny, in, out, FFTW_ESTIMATE);
  for (std::size_t k = 0; k < chi.size(); ++k)
    in[k] = chi[k];
  fftw_execute(plan);
  fftw_destroy_plan(plan);
  const double dx = L[0] / nx, dy = L[1] / ny, area = L[0] * L[1];
  const double k_min = 2 * std::numbers::pi / std::max(L[0], L[1]);
  const double log_lo = std::log(k_min) - 1e-9, log_hi = std::log(k_max);
  std::vector<double> s(bins, 0), s2(bins, 0), sk(bins, 0), w(bins, 0);
  for (int i = 0; i < nx; ++i) {
    const int m = i <= nx / 2 ? i : i - nx;
    const double kx = 2 * std::numbers::pi * m / L[0];
    for (int j = 0; j < nyc; ++j) {
      if (m == 0 && j == 0)
        continue; // the mean: Phi^2 A, not a fluctuation
      const double ky = 2 * std::numbers::pi * j / L[1];
      const double kk = std::hypot(kx, ky);
      if (kk > k_max)
        continue;
      const int b = int((std::log(kk) - log_lo) / (log_hi - log_lo) * bins);
      if (b < 0 || b >= bins)
        continue;
      const auto& c = out[std::size_t(i) * nyc + j];
      // chi^(k) ~ sum chi e^(-ik.x) dx dy; eq. (25).
      const double I = (c[0] * c[0] + c[1] * c[1]) * dx * dx * dy * dy / area;
      // The half spectrum stands for k and -k, except on the lines j = 0 and j = ny/2.
      const double weight = (j == 0 || (ny % 2 == 0 && j == ny / 2)) ? 1.0 : 2.0;
      s[b] += weight * I, s2[b] += weight * I * I, sk[b] += weight * kk, w[b] += weight;
    }
  }
  DensitySpectra d;
  ScatteringCurve& c = d.scattering;
  for (int b = 0; b < bins; ++b) {
    if (w[b] == 0)
      continue;
    const double mean = s[b] / w[b];
    const double var = std::max(0.0, s2[b] / w[b] - mean * mean);
    c.k.push_back(sk[b] / w[b]);
    c.I.push_back(mean);
    c.I_error.push_back(std::sqrt(var / w[b]));
    c.count.push_back(w[b]);
  }
  if (r_max > 0) {
    // C(r) - Phi^2 = (1/N) sum_R (chi(R) - Phi)(chi(R + r) - Phi) = backward(|X|^2, X(0) = 0) / N^2
    // with X the unnormalised forward transform (FFTW's backward is unnormalised too).
    const double nodes = double(nx) * double(ny);
    for (std::size_t q = 0; q < std::size_t(nx) * nyc; ++q) {
      out[q][0] = (out[q][0] * out[q][0] + out[q][1] * out[q][1]) / (nodes * nodes);
      out[q][1] = 0;
    }
    out[0][0] = 0;
    fftw_plan back = fftw_plan_dft_c2r_2d(nx, ny, out, in, FFTW_ESTIMATE);
    fftw_execute(back);
    fftw_destroy_plan(back);
    const int rb = int(std::floor(r_max / r_bin));
    std::vector<double> cs(rb, 0), cr(rb, 0), cn(rb, 0);
    for (int i = 0; i < nx; ++i) {
      const double x = std::min(i, nx - i) * dx;
      for (int j = 0; j < ny; ++j) {
        const double r = std::hypot(x, std::min(j, ny - j) * dy);
        const int b = int(r / r_bin);
        if (b >= rb)
          continue;
        cs[b] += in[std::size_t(i) * ny + j], cr[b] += r, cn[b] += 1;
      }
    }
    for (int b = 0; b < rb; ++b) {
      if (cn[b] == 0)
        continue;
      d.correlation.r.push_back(cr[b] / cn[b]);
      d.correlation.C.push_back(cs[b] / cn[b]);
      d.correlation.count.push_back(cn[b]);
    }
  }
  fftw_free(in);
  fftw_free(out);
  return d;
}

ScatteringCurve scattering_function(const std::vector<std::uint8_t>& chi, const Vec<2>& L, int nx,
                                    int ny, double k_max, int bins) {
  return density_spectra(chi, L, nx, ny, k_max, bins, 0.0, 0.0).scattering;
}

ScatteringCurve pooled_scattering(std::span<const ScatteringCurve> curves) {
  ScatteringCurve out;
  const ScatteringCurve* ref = nullptr;
  for (const auto& c : curves)
    if (!ref || c.k.size() > ref->k.size())
      ref = &c;
  if (!ref || ref->k.empty())
    return out;
  std::vector<double> edges; // upper edges of the common bins but the last
  for (std::size_t b = 0; b + 1 < ref->k.size(); ++b)
    edges.push_back(std::sqrt(ref->k[b] * ref->k[b + 1]));
  const std::size_t bins = ref->k.size();
  std::vector<double> s(bins, 0), sk(bins, 0), w(bins, 0), e2(bins, 0);
  for (const auto& c : curves)
    for (std::size_t i = 0; i < c.k.size(); ++i) {
      const auto b =
          std::size_t(std::upper_bound(edges.begin(), edges.end(), c.k[i]) - edges.begin());
      s[b] += c.count[i] * c.I[i], sk[b] += c.count[i] * c.k[i], w[b] += c.count[i];
      e2[b] += c.count[i] * c.count[i] * c.I_error[i] * c.I_error[i];
    }
  for (std::size_t b = 0; b < bins; ++b) {
    if (w[b] == 0)
      continue;
    out.k.push_back(sk[b] / w[b]);
    out.I.push_back(s[b] / w[b]);
    out.I_error.push_back(std::sqrt(e2[b]) / w[b]);
    out.count.push_back(w[b]);
  }
  return out;
}

double legendre_p(double nu, double x) {
  GRANPACK_CHECK(x >= 0 && x <= 1, "legendre_p: need 0 <= x <= 1"); // x = 0: xi beyond double range
  const double y = 0.5 * (1 - x); // < 1/2: the series converges at least like 2^-n
  double term = 1, sum = 1;
  for (int n = 0; n < 2000; ++n) {
    term *= (n - nu) * (nu + 1 + n) / double((n + 1) * (n + 1)) * y;
    sum += term;
    if (std::abs(term) < 1e-17 * std::abs(sum))
      break;
  }
  return sum;
}

double fractal_blob_intensity(double k, double d_f, double xi, double amplitude) {
  const double p = 1 / xi, s = std::hypot(p, k);
  // xi = 0 or NaN (a minimiser's trial step): NaN, which the fit's residual treats as off-domain.
  if (!(p / s >= 0 && p / s <= 1))
    return std::numeric_limits<double>::quiet_NaN();
  return amplitude * 2 * std::numbers::pi * std::tgamma(d_f) * std::pow(s, -d_f) *
         legendre_p(d_f - 1, p / s);
}

namespace {

/// Weighted residuals sqrt(w_i) (log I_i - log(Cst + eq. 28)) for parameters
/// (Cst / I_scale, log amplitude, d_F, log xi).
struct BlobResiduals {
  using Scalar = double;
  using InputType = Eigen::VectorXd;
  using ValueType = Eigen::VectorXd;
  using JacobianType = Eigen::MatrixXd;
  enum { InputsAtCompileTime = Eigen::Dynamic, ValuesAtCompileTime = Eigen::Dynamic };
  const std::vector<double>* kp;
  const std::vector<double>* logIp;
  const std::vector<double>* sqrt_wp;
  double scale;
  BlobResiduals(const std::vector<double>& k_, const std::vector<double>& logI_,
                const std::vector<double>& sqrt_w_, double scale_)
      : kp(&k_), logIp(&logI_), sqrt_wp(&sqrt_w_), scale(scale_) {}
  int inputs() const { return 4; }
  int values() const { return int(kp->size()); }
  int operator()(const Eigen::VectorXd& th, Eigen::VectorXd& f) const {
    const auto& k = *kp;
    const auto& logI = *logIp;
    for (std::size_t i = 0; i < k.size(); ++i) {
      const double model =
          th[0] * scale + fractal_blob_intensity(k[i], th[2], std::exp(th[3]), std::exp(th[1]));
      // A non-positive model is outside the domain of the log: a large residual steers back.
      f[i] = (*sqrt_wp)[i] * (model > 0 ? logI[i] - std::log(model) : 1e3);
    }
    return 0;
  }
};

/// Covariance of least-squares parameters from the weighted Jacobian J, scaled by the weighted
/// residual variance chi2 / (N - p); empty when J^T J is singular (relative eigenvalue below
/// 1e-12 after scaling each column to unit norm: a parameter the data do not constrain, as
/// xi when the model has become a pure power law).
Eigen::MatrixXd covariance(const Eigen::MatrixXd& J, double chi2) {
  const Eigen::Index p = J.cols(), n = J.rows();
  if (n <= p)
    return {};
  Eigen::VectorXd norm = J.colwise().norm().transpose();
  if (!(norm.minCoeff() > 0) || !norm.allFinite())
    return {};
  const Eigen::MatrixXd Js = J * norm.cwiseInverse().asDiagonal();
  const Eigen::MatrixXd A = Js.transpose() * Js;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(A);
  const auto& ev = es.eigenvalues();
  if (!(ev.minCoeff() > 1e-12 * ev.maxCoeff()))
    return {};
  const Eigen::MatrixXd inv =
      es.eigenvectors() * ev.cwiseInverse().asDiagonal() * es.eigenvectors().transpose();
  return norm.cwiseInverse().asDiagonal() * inv * norm.cwiseInverse().asDiagonal() *
         (chi2 / double(n - p));
}

/// Fills the errors of f from the covariance of (.., d_F at index id, log xi or -1/xi at ix)
/// and decides whether the fit is determined.
void finish_fit(FractalFit& f, const Eigen::MatrixXd& cov, int id, int ix, bool xi_is_log,
                double xi_max) {
  if (!f.converged) {
    f.reason = "the minimiser did not converge";
  } else if (!(f.xi > 0) || !std::isfinite(f.xi) || f.xi > xi_max) {
    f.reason = "xi unbounded (beyond the cell: the data show no cut-off of the power law)";
  } else if (cov.size() == 0) {
    f.reason = "singular covariance (a parameter is not constrained by the data)";
  } else {
    f.d_f_error = std::sqrt(std::max(0.0, cov(id, id)));
    // xi = exp(th) -> sigma_xi = xi sigma_th; xi = -1/c -> sigma_xi = xi^2 sigma_c.
    f.xi_error = (xi_is_log ? f.xi : f.xi * f.xi) * std::sqrt(std::max(0.0, cov(ix, ix)));
    if (!(f.d_f_error > 0) || !(f.xi_error > 0) || !std::isfinite(f.d_f_error) ||
        !std::isfinite(f.xi_error))
      f.reason = "zero or non-finite parameter errors";
    else
      f.determined = true;
  }
}

} // namespace

FractalFit fit_fractal_blob(const ScatteringCurve& c, double k_lo, double k_hi, double phi,
                            double xi_max) {
  std::vector<double> k, logI, sqrt_w;
  for (std::size_t i = 0; i < c.k.size(); ++i)
    if (c.k[i] >= k_lo && c.k[i] <= k_hi && c.I[i] > 0)
      k.push_back(c.k[i]), logI.push_back(std::log(c.I[i])),
          sqrt_w.push_back(std::sqrt(std::max(1.0, c.count[i])));
  FractalFit best;
  best.points = int(k.size());
  if (k.size() < 6) {
    best.reason = "fewer than 6 points in the window";
    return best;
  }
  best.lo = k.front(), best.hi = k.back();
  best.reason = "no start converged to 0.5 < d_F < 2.5";
  const double scale = std::exp(logI.back()); // the constant's natural size: I at k_hi
  double best_cost = std::numeric_limits<double>::infinity();
  Eigen::MatrixXd best_cov;
  for (double xi0 :
       {0.3 / k.front(), 1.0 / k.front(), 3.0 / k.back(), 10.0 / k.back(), 10.0 / k.front()})
    for (double d0 : {1.5, 1.9}) {
      Eigen::VectorXd th(4);
      th << 0.0, 0.0, d0, std::log(xi0);
      th[1] = std::log(std::exp(logI.front()) / fractal_blob_intensity(k.front(), d0, xi0, 1.0));
      Eigen::NumericalDiff<BlobResiduals> fn(BlobResiduals(k, logI, sqrt_w, scale));
      Eigen::LevenbergMarquardt<Eigen::NumericalDiff<BlobResiduals>> lm(fn);
      lm.parameters.maxfev = 4000;
      const auto status = lm.minimize(th);
      if (!(th[2] > 0.5 && th[2] < 2.5) || !std::isfinite(th[3]))
        continue;
      Eigen::VectorXd f(k.size());
      fn(th, f);
      const double cost = f.squaredNorm();
      if (!(cost < best_cost))
        continue;
      best_cost = cost;
      Eigen::MatrixXd J(k.size(), 4);
      fn.df(th, J);
      best_cov = covariance(J, cost);
      double rms = 0;
      for (std::size_t i = 0; i < k.size(); ++i)
        rms += (f[i] / sqrt_w[i]) * (f[i] / sqrt_w[i]);
      best.constant = th[0] * scale;
      best.amplitude = std::exp(th[1]);
      best.d_f = th[2];
      best.xi = std::exp(th[3]);
      best.length_l =
          std::abs(2 - best.d_f) > 1e-9 ? std::pow(best.amplitude / phi, 1 / (2 - best.d_f)) : 0.0;
      best.rms_log_residual = std::sqrt(rms / double(k.size()));
      using namespace Eigen::LevenbergMarquardtSpace;
      best.converged = status != ImproperInputParameters && status != TooManyFunctionEvaluation &&
                       status != UserAsked;
    }
  if (std::isfinite(best_cost)) {
    best.reason.clear();
    finish_fit(best, best_cov, 2, 3, true, xi_max);
  }
  return best;
}

FractalFit fit_fractal_real_space(const CorrelationCurve& c, double r_lo, double r_hi, double phi,
                                  double xi_max) {
  FractalFit f;
  std::vector<double> r, y;
  for (std::size_t i = 0; i < c.r.size(); ++i) {
    if (c.r[i] < r_lo)
      continue;
    if (c.r[i] > r_hi || !(c.C[i] > 0))
      break; // the window ends at the first C - Phi^2 <= 0
    r.push_back(c.r[i]), y.push_back(c.C[i]);
  }
  f.points = int(r.size());
  if (r.size() < 6) { // 3 parameters; with fewer than 6 points any curve fits
    f.reason = "fewer than 6 points with C - Phi^2 > 0 in the window";
    return f;
  }
  f.lo = r.front(), f.hi = r.back();
  // Columns scaled by r_hi so that the normal equations are well conditioned for any unit.
  const Eigen::Index n = Eigen::Index(r.size());
  Eigen::MatrixXd A(n, 3);
  Eigen::VectorXd b(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double w = y[std::size_t(i)]; // sqrt of the weight y^2
    A(i, 0) = w, A(i, 1) = w * std::log(r[std::size_t(i)] / f.hi),
         A(i, 2) = w * r[std::size_t(i)] / f.hi;
    b[i] = w * std::log(y[std::size_t(i)]);
  }
  const Eigen::VectorXd th = A.colPivHouseholderQr().solve(b);
  const Eigen::VectorXd res = b - A * th;
  double rms = 0;
  for (Eigen::Index i = 0; i < n; ++i)
    rms += (res[i] / y[std::size_t(i)]) * (res[i] / y[std::size_t(i)]);
  f.rms_log_residual = std::sqrt(rms / double(n));
  f.d_f = th[1] + 2;
  const double c2 = th[2] / f.hi; // -1/xi
  f.xi = c2 < 0 ? -1 / c2 : std::numeric_limits<double>::infinity();
  // ln y = th0 + (d-2) ln(r / r_hi) - r/xi: the amplitude Phi l^(2-d) = exp(th0) r_hi^(2-d).
  f.amplitude = std::exp(th[0]) * std::pow(f.hi, 2 - f.d_f);
  f.length_l = std::abs(2 - f.d_f) > 1e-9 ? std::pow(f.amplitude / phi, 1 / (2 - f.d_f)) : 0.0;
  f.converged = th.allFinite();
  Eigen::MatrixXd cov = covariance(A, res.squaredNorm());
  if (cov.size())
    cov(2, 2) /= f.hi * f.hi; // from th[2] to c2 = th[2] / r_hi
  finish_fit(f, cov, 1, 2, false, xi_max);
  return f;
}

std::string fractal_regime_failure(const FractalFit& f, double a, double l_cell) {
  if (!f.determined)
    return "fit undetermined: " + f.reason;
  if (f.points < 6)
    return "fewer than 6 points";
  if (!(f.xi - 2 * f.xi_error > a))
    return "xi - 2 sigma_xi <= a";
  if (!(f.xi + 2 * f.xi_error < 0.5 * l_cell))
    return "xi + 2 sigma_xi >= L/2";
  if (!(f.d_f_error < 0.2))
    return "sigma_dF >= 0.2";
  if (!(f.d_f - 2 * f.d_f_error > 1))
    return "d_F - 2 sigma_dF <= 1";
  if (!(f.d_f + 2 * f.d_f_error < 2.1))
    return "d_F + 2 sigma_dF >= 2.1";
  return {};
}

HoleStatistics hole_statistics(const std::vector<std::uint8_t>& chi, const Vec<2>& L, int nx,
                               int ny) {
  GRANPACK_CHECK(chi.size() == std::size_t(nx) * std::size_t(ny), "hole_statistics: mesh size");
  const double dx = L[0] / nx, dy = L[1] / ny;
  std::vector<std::int32_t> label(chi.size(), -1);
  // Image offsets of each visited node relative to its hole's first node (unwrapping).
  std::vector<std::int16_t> ox(chi.size(), 0), oy(chi.size(), 0);
  HoleStatistics h;
  std::deque<std::size_t> queue;
  for (std::size_t start = 0; start < chi.size(); ++start) {
    if (chi[start] || label[start] >= 0)
      continue;
    const std::int32_t id = std::int32_t(h.holes++);
    label[start] = id;
    queue.push_back(start);
    bool wraps = false;
    double n = 0, sx = 0, sy = 0, sxx = 0;
    while (!queue.empty()) {
      const std::size_t u = queue.front();
      queue.pop_front();
      const int i = int(u / ny), j = int(u % ny);
      const double x = (i + 0.5 + double(ox[u]) * nx) * dx, y = (j + 0.5 + double(oy[u]) * ny) * dy;
      n += 1, sx += x, sy += y, sxx += x * x + y * y;
      const int di[4] = {1, -1, 0, 0}, dj[4] = {0, 0, 1, -1};
      for (int q = 0; q < 4; ++q) {
        int ii = i + di[q], jj = j + dj[q];
        std::int16_t wx = ox[u], wy = oy[u];
        if (ii < 0)
          ii += nx, --wx;
        if (ii >= nx)
          ii -= nx, ++wx;
        if (jj < 0)
          jj += ny, --wy;
        if (jj >= ny)
          jj -= ny, ++wy;
        const std::size_t v = std::size_t(ii) * ny + std::size_t(jj);
        if (chi[v])
          continue;
        if (label[v] < 0) {
          label[v] = id, ox[v] = wx, oy[v] = wy;
          queue.push_back(v);
        } else if (ox[v] != wx || oy[v] != wy) {
          wraps = true; // reached again through another image: the hole wraps the cell
        }
      }
    }
    if (wraps) {
      ++h.wrapping_holes;
      continue;
    }
    const double r2 = sxx / n - (sx * sx + sy * sy) / (n * n);
    h.radii.push_back(std::sqrt(std::max(0.0, 2 * r2))); // eq. (29)
    h.nodes.push_back(n);
  }
  double num = 0, den = 0;
  for (std::size_t k = 0; k < h.radii.size(); ++k) {
    num += h.nodes[k] * h.radii[k], den += h.nodes[k];
    h.largest_radius = std::max(h.largest_radius, h.radii[k]);
  }
  h.weighted_mean_radius = den > 0 ? num / den : 0.0; // eq. (30)
  return h;
}

} // namespace granpack
