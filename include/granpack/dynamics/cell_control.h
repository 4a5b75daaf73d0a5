#pragma once
// Stress control of the cell lengths, [AR] eq. (7) ([GRC] eq. 3):
//   M d2L_a/dt2 = (Omega / L_a) (sigma_aa - Sigma_a),
// sigma from eq. (8) with compressive stresses positive: a cell whose measured stress exceeds
// the prescribed one expands. Axes may instead keep a fixed length. The strain rate
// |dL_a/dt| / L_a may be capped (the inertia number cap of eq. 23 converted by the caller to
// a strain rate, or a direct eps_dot_max).
#include <array>
#include <limits>

#include "granpack/core/cell.h"

namespace granpack {

template <int dim> struct CellControl {
  double mass = 1.0;                  ///< generalised mass M, kg
  Vec<dim> target = Vec<dim>::Zero(); ///< prescribed Sigma_a, Pa
  std::array<bool, dim> fixed{};      ///< axes kept at constant length
  double max_strain_rate = std::numeric_limits<double>::infinity(); ///< 1/s

  /// Ldot += h * (Omega/L_a)(sigma_aa - Sigma_a)/M, then the strain-rate cap.
  void kick(Cell<dim>& cell, const Vec<dim>& sigma_diag, double h) const {
    const double omega = cell.volume();
    for (int a = 0; a < dim; ++a) {
      if (fixed[a]) {
        cell.rate[a] = 0;
        continue;
      }
      cell.rate[a] += h * omega / cell.length[a] * (sigma_diag[a] - target[a]) / mass;
      const double cap = max_strain_rate * cell.length[a];
      if (cell.rate[a] > cap)
        cell.rate[a] = cap;
      if (cell.rate[a] < -cap)
        cell.rate[a] = -cap;
    }
  }
  /// L += dt Ldot.
  static void drift(Cell<dim>& cell, double dt) { cell.length += dt * cell.rate; }
};

} // namespace granpack
