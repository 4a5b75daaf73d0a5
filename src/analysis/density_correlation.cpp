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

std::vector<std::uint8_t> rasterize_disks(std::span<const Disk> disks, const Vec<2>& L, int nx, int ny) {
  GRANPACK_CHECK(nx > 0 && ny > 0, "rasterize_disks: mesh must have nodes");
  std::vector<std::uint8_t> chi(std::size_t(nx) * std::size_t(ny), 0);
  const double dx = L[0] / nx, dy = L[1] / ny;
  for (const Disk& d : disks) {
    // Centre wrapped into the cell; the node loop wraps indices, so one image suffices.
    const double cx = d.center[0] - L[0] * std::floor(d.center[0] / L[0]);
    const double cy = d.center[1] - L[1] * std::floor(d.center[1] / L[1]);
    const int i0 = int(std::floor((cx - d.radius) / dx - 0.5)), i1 = int(std::ceil((cx + d.radius) / dx - 0.5));
    const int j0 = int(std::floor((cy - d.radius) / dy - 0.5)), j1 = int(std::ceil((cy + d.radius) / dy - 0.5));
    const double r2 = d.radius * d.radius;
    for (int i = i0; i <= i1; ++i) {
      const double x = (i + 0.5) * dx - cx;
      const int iw = ((i % nx) + nx) % nx;
      for (int j = j0; j <= j1; ++j) {
        const double y = (j + 0.5) * dy - cy;
        if (x * x + y * y < r2) chi[std::size_t(iw) * ny + std::size_t(((j % ny) + ny) % ny)] = 1;
      }
    }
  }
  return chi;
}

ScatteringCurve scattering_function(const std::vector<std::uint8_t>& chi, const Vec<2>& L, int nx,
                                    int ny, double k_max, int bins) {
  GRANPACK_CHECK(chi.size() == std::size_t(nx) * std::size_t(ny), "scattering_function: mesh size");
  GRANPACK_CHECK(bins > 0 && k_max > 0, "scattering_function: need bins > 0 and k_max > 0");
  const int nyc = ny / 2 + 1;
  double* in = fftw_alloc_real(std::size_t(nx) * ny);
  fftw_complex* out = fftw_alloc_complex(std::size_t(nx) * nyc);
  GRANPACK_CHECK(in && out, "scattering_function: out of memory for a " << nx << " x " << ny << " FFT");
  fftw_plan plan = fftw_plan_dft_r2c_2d(nx, ny, in, out, FFTW_ESTIMATE);
  for (std::size_t k = 0; k < chi.size(); ++k) in[k] = chi[k];
  fftw_execute(plan);
  const double dx = L[0] / nx, dy = L[1] / ny, area = L[0] * L[1];
  const double k_min = 2 * std::numbers::pi / std::max(L[0], L[1]);
  const double log_lo = std::log(k_min) - 1e-9, log_hi = std::log(k_max);
  std::vector<double> s(bins, 0), s2(bins, 0), sk(bins, 0), w(bins, 0);
  for (int i = 0; i < nx; ++i) {
    const int m = i <= nx / 2 ? i : i - nx;
    const double kx = 2 * std::numbers::pi * m / L[0];
    for (int j = 0; j < nyc; ++j) {
      if (m == 0 && j == 0) continue;  // the mean: Phi^2 A, not a fluctuation
      const double ky = 2 * std::numbers::pi * j / L[1];
      const double kk = std::hypot(kx, ky);
      if (kk > k_max) continue;
      const int b = int((std::log(kk) - log_lo) / (log_hi - log_lo) * bins);
      if (b < 0 || b >= bins) continue;
      const auto& c = out[std::size_t(i) * nyc + j];
      // chi^(k) ~ sum chi e^(-ik.x) dx dy; eq. (25).
      const double I = (c[0] * c[0] + c[1] * c[1]) * dx * dx * dy * dy / area;
      // The half spectrum stands for k and -k, except on the lines j = 0 and j = ny/2.
      const double weight = (j == 0 || (ny % 2 == 0 && j == ny / 2)) ? 1.0 : 2.0;
      s[b] += weight * I, s2[b] += weight * I * I, sk[b] += weight * kk, w[b] += weight;
    }
  }
  fftw_destroy_plan(plan);
  fftw_free(in);
  fftw_free(out);
  ScatteringCurve c;
  for (int b = 0; b < bins; ++b) {
    if (w[b] == 0) continue;
    const double mean = s[b] / w[b];
    const double var = std::max(0.0, s2[b] / w[b] - mean * mean);
    c.k.push_back(sk[b] / w[b]);
    c.I.push_back(mean);
    c.I_error.push_back(std::sqrt(var / w[b]));
    c.count.push_back(w[b]);
  }
  return c;
}

double legendre_p(double nu, double x) {
  GRANPACK_CHECK(x > 0 && x <= 1, "legendre_p: need 0 < x <= 1");
  const double y = 0.5 * (1 - x);  // < 1/2: the series converges at least like 2^-n
  double term = 1, sum = 1;
  for (int n = 0; n < 2000; ++n) {
    term *= (n - nu) * (nu + 1 + n) / double((n + 1) * (n + 1)) * y;
    sum += term;
    if (std::abs(term) < 1e-17 * std::abs(sum)) break;
  }
  return sum;
}

double fractal_blob_intensity(double k, double d_f, double xi, double amplitude) {
  const double p = 1 / xi, s = std::hypot(p, k);
  return amplitude * 2 * std::numbers::pi * std::tgamma(d_f) * std::pow(s, -d_f) * legendre_p(d_f - 1, p / s);
}

namespace {

/// Residuals log I_i - log(Cst + eq. 28) for parameters (Cst / I_scale, log amplitude, d_F, log xi).
struct BlobResiduals {
  using Scalar = double;
  using InputType = Eigen::VectorXd;
  using ValueType = Eigen::VectorXd;
  using JacobianType = Eigen::MatrixXd;
  enum { InputsAtCompileTime = Eigen::Dynamic, ValuesAtCompileTime = Eigen::Dynamic };
  const std::vector<double>* kp;
  const std::vector<double>* logIp;
  double scale;
  BlobResiduals(const std::vector<double>& k_, const std::vector<double>& logI_, double scale_)
      : kp(&k_), logIp(&logI_), scale(scale_) {}
  int inputs() const { return 4; }
  int values() const { return int(kp->size()); }
  int operator()(const Eigen::VectorXd& th, Eigen::VectorXd& f) const {
    const auto& k = *kp;
    const auto& logI = *logIp;
    for (std::size_t i = 0; i < k.size(); ++i) {
      const double model = th[0] * scale + fractal_blob_intensity(k[i], th[2], std::exp(th[3]), std::exp(th[1]));
      // A non-positive model is outside the domain of the log: a large residual steers back.
      f[i] = model > 0 ? logI[i] - std::log(model) : 1e3;
    }
    return 0;
  }
};

}  // namespace

FractalFit fit_fractal_blob(const ScatteringCurve& c, double k_lo, double k_hi, double phi) {
  std::vector<double> k, logI;
  for (std::size_t i = 0; i < c.k.size(); ++i)
    if (c.k[i] >= k_lo && c.k[i] <= k_hi && c.I[i] > 0) k.push_back(c.k[i]), logI.push_back(std::log(c.I[i]));
  FractalFit best;
  best.points = int(k.size());
  if (k.size() < 6) return best;
  const double scale = std::exp(logI.back());  // the constant's natural size: I at k_hi
  double best_rms = std::numeric_limits<double>::infinity();
  for (double xi0 : {0.3 / k.front(), 1.0 / k.front(), 3.0 / k.back(), 10.0 / k.back()})
    for (double d0 : {1.5, 1.9}) {
      Eigen::VectorXd th(4);
      th << 0.0, 0.0, d0, std::log(xi0);
      th[1] = std::log(std::exp(logI.front()) / fractal_blob_intensity(k.front(), d0, xi0, 1.0));
      Eigen::NumericalDiff<BlobResiduals> fn(BlobResiduals(k, logI, scale));
      Eigen::LevenbergMarquardt<Eigen::NumericalDiff<BlobResiduals>> lm(fn);
      lm.parameters.maxfev = 4000;
      const auto status = lm.minimize(th);
      if (!(th[2] > 0.5 && th[2] < 2.5) || !std::isfinite(th[3])) continue;
      Eigen::VectorXd f(k.size());
      fn(th, f);
      const double rms = std::sqrt(f.squaredNorm() / double(k.size()));
      if (!(rms < best_rms)) continue;
      best_rms = rms;
      Eigen::MatrixXd J(k.size(), 4);
      fn.df(th, J);
      const Eigen::MatrixXd cov = (J.transpose() * J).completeOrthogonalDecomposition().pseudoInverse() *
                                  (f.squaredNorm() / double(std::max<std::size_t>(1, k.size() - 4)));
      best.constant = th[0] * scale;
      best.amplitude = std::exp(th[1]);
      best.d_f = th[2];
      best.xi = std::exp(th[3]);
      best.d_f_error = std::sqrt(std::max(0.0, cov(2, 2)));
      best.xi_error = best.xi * std::sqrt(std::max(0.0, cov(3, 3)));
      best.length_l = std::abs(2 - best.d_f) > 1e-9 ? std::pow(best.amplitude / phi, 1 / (2 - best.d_f)) : 0.0;
      best.rms_log_residual = rms;
      best.converged = status != Eigen::LevenbergMarquardtSpace::ImproperInputParameters;
    }
  return best;
}

HoleStatistics hole_statistics(const std::vector<std::uint8_t>& chi, const Vec<2>& L, int nx, int ny) {
  GRANPACK_CHECK(chi.size() == std::size_t(nx) * std::size_t(ny), "hole_statistics: mesh size");
  const double dx = L[0] / nx, dy = L[1] / ny;
  std::vector<std::int32_t> label(chi.size(), -1);
  // Image offsets of each visited node relative to its hole's first node (unwrapping).
  std::vector<std::int16_t> ox(chi.size(), 0), oy(chi.size(), 0);
  HoleStatistics h;
  std::deque<std::size_t> queue;
  for (std::size_t start = 0; start < chi.size(); ++start) {
    if (chi[start] || label[start] >= 0) continue;
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
        if (ii < 0) ii += nx, --wx;
        if (ii >= nx) ii -= nx, ++wx;
        if (jj < 0) jj += ny, --wy;
        if (jj >= ny) jj -= ny, ++wy;
        const std::size_t v = std::size_t(ii) * ny + std::size_t(jj);
        if (chi[v]) continue;
        if (label[v] < 0) {
          label[v] = id, ox[v] = wx, oy[v] = wy;
          queue.push_back(v);
        } else if (ox[v] != wx || oy[v] != wy) {
          wraps = true;  // reached again through another image: the hole wraps the cell
        }
      }
    }
    if (wraps) {
      ++h.wrapping_holes;
      continue;
    }
    const double r2 = sxx / n - (sx * sx + sy * sy) / (n * n);
    h.radii.push_back(std::sqrt(std::max(0.0, 2 * r2)));  // eq. (29)
    h.nodes.push_back(n);
  }
  double num = 0, den = 0;
  for (std::size_t k = 0; k < h.radii.size(); ++k) {
    num += h.nodes[k] * h.radii[k], den += h.nodes[k];
    h.largest_radius = std::max(h.largest_radius, h.radii[k]);
  }
  h.weighted_mean_radius = den > 0 ? num / den : 0.0;  // eq. (30)
  return h;
}

}  // namespace granpack
