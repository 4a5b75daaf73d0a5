#pragma once
// Translational order of a configuration with respect to the Bragg peaks of an earlier one:
// how much of a starting lattice a melted gas (or the packing made from it) still remembers.
//
// For a wave vector k of the periodic cell, k = 2 pi (m_1/L_1, ..., m_d/L_d) with integer m,
//   rho_k = | (1/N) sum_j exp(i k . x_j) |.
// A perfect lattice has rho_k = 1 on its reciprocal vectors; N uncorrelated positions give
// rho_k of order 1/sqrt(N) (mean sqrt(pi/(4N))). The `ed_gas` stage records the peaks of its
// starting configuration and reports their mean rho_k at its end ("lattice_order" in
// report.json), so a melt that is too short shows up as a value well above 1/sqrt(N)
// (docs/reproduction.md, "Melting").
#include <array>
#include <span>
#include <vector>

#include "granpack/core/vec.h"

namespace granpack {

template <int dim> struct BraggPeaks {
  std::vector<std::array<int, dim>> m; ///< integer wave-vector indices, one of each +-k pair
};

/// rho_k for the wave vector of indices m in the periodic cell of lengths L.
template <int dim>
double translational_order(std::span<const Vec<dim>> x, const Vec<dim>& L,
                           const std::array<int, dim>& m);

/// The wave vectors with 0 < |m_alpha| <= m_max (half space) whose rho_k is at least
/// `threshold`: the Bragg peaks of a lattice. Cost: (2 m_max + 1)^dim / 2 vectors times N.
template <int dim>
BraggPeaks<dim> find_bragg_peaks(std::span<const Vec<dim>> x, const Vec<dim>& L, int m_max,
                                 double threshold);

/// Mean rho_k over the peaks (0 when there are none).
template <int dim>
double mean_translational_order(std::span<const Vec<dim>> x, const Vec<dim>& L,
                                const BraggPeaks<dim>& peaks);

} // namespace granpack
