#include "granpack/analysis/translational_order.h"

#include <cmath>
#include <complex>
#include <numbers>

namespace granpack {
namespace {

using C = std::complex<double>;

/// e[j][alpha][m + m_max] = exp(2 pi i m x_j,alpha / L_alpha): the separable factors, so that a
/// wave vector costs dim - 1 complex products per grain instead of a sin and a cos.
template <int dim>
std::vector<std::array<std::vector<C>, dim>> factors(std::span<const Vec<dim>> x, const Vec<dim>& L,
                                                     int m_max) {
  std::vector<std::array<std::vector<C>, dim>> e(x.size());
  for (std::size_t j = 0; j < x.size(); ++j)
    for (int a = 0; a < dim; ++a) {
      auto& row = e[j][a];
      row.resize(2 * m_max + 1);
      const double phase = 2.0 * std::numbers::pi * x[j][a] / L[a];
      for (int m = -m_max; m <= m_max; ++m)
        row[m + m_max] = std::polar(1.0, m * phase);
    }
  return e;
}

template <int dim>
double rho(const std::vector<std::array<std::vector<C>, dim>>& e, const std::array<int, dim>& m,
           int m_max) {
  C sum = 0.0;
  for (const auto& ej : e) {
    C p = ej[0][m[0] + m_max];
    for (int a = 1; a < dim; ++a)
      p *= ej[a][m[a] + m_max];
    sum += p;
  }
  return e.empty() ? 0.0 : std::abs(sum) / static_cast<double>(e.size());
}

int max_index(const std::array<int, 3>& m, int d) {
  int r = 0;
  for (int a = 0; a < d; ++a)
    r = std::max(r, std::abs(m[a]));
  return r;
}

} // namespace

template <int dim>
double translational_order(std::span<const Vec<dim>> x, const Vec<dim>& L,
                           const std::array<int, dim>& m) {
  int m_max = 0;
  for (int a = 0; a < dim; ++a)
    m_max = std::max(m_max, std::abs(m[a]));
  return rho<dim>(factors<dim>(x, L, m_max), m, m_max);
}

template <int dim>
BraggPeaks<dim> find_bragg_peaks(std::span<const Vec<dim>> x, const Vec<dim>& L, int m_max,
                                 double threshold) {
  BraggPeaks<dim> peaks;
  const auto e = factors<dim>(x, L, m_max);
  std::array<int, 3> m{0, 0, 0};
  const int side = 2 * m_max + 1;
  const int count = dim == 2 ? side * side : side * side * side;
  for (int c = 0; c < count; ++c) {
    int r = c;
    for (int a = 0; a < dim; ++a) {
      m[a] = r % side - m_max;
      r /= side;
    }
    // Half space: k and -k have the same rho_k; keep the one whose first non-zero index is > 0.
    int first = 0;
    for (int a = 0; a < dim && first == 0; ++a)
      first = m[a];
    if (first <= 0 || max_index(m, dim) == 0)
      continue;
    std::array<int, dim> md;
    for (int a = 0; a < dim; ++a)
      md[a] = m[a];
    if (rho<dim>(e, md, m_max) >= threshold)
      peaks.m.push_back(md);
  }
  return peaks;
}

template <int dim>
double mean_translational_order(std::span<const Vec<dim>> x, const Vec<dim>& L,
                                const BraggPeaks<dim>& peaks) {
  if (peaks.m.empty())
    return 0.0;
  int m_max = 0;
  for (const auto& m : peaks.m)
    for (int a = 0; a < dim; ++a)
      m_max = std::max(m_max, std::abs(m[a]));
  const auto e = factors<dim>(x, L, m_max);
  double s = 0.0;
  for (const auto& m : peaks.m)
    s += rho<dim>(e, m, m_max);
  return s / static_cast<double>(peaks.m.size());
}

template double translational_order<2>(std::span<const Vec<2>>, const Vec<2>&,
                                       const std::array<int, 2>&);
template double translational_order<3>(std::span<const Vec<3>>, const Vec<3>&,
                                       const std::array<int, 3>&);
template BraggPeaks<2> find_bragg_peaks<2>(std::span<const Vec<2>>, const Vec<2>&, int, double);
template BraggPeaks<3> find_bragg_peaks<3>(std::span<const Vec<3>>, const Vec<3>&, int, double);
template double mean_translational_order<2>(std::span<const Vec<2>>, const Vec<2>&,
                                            const BraggPeaks<2>&);
template double mean_translational_order<3>(std::span<const Vec<3>>, const Vec<3>&,
                                            const BraggPeaks<3>&);

} // namespace granpack
