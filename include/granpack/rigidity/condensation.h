#pragma once
// Elimination of the grain unknowns onto the strain coordinates: the Schur complement
//     C = K_ee - K_eu K_uu^{-1} K_ue      (dim x dim, in the scaled unknowns e = eps L)
// with one factorisation of K_uu and dim solves. Then the macroscopic moduli for diagonal
// strains: with Kc = L C L (physical, Delta(Omega Sigma) = Kc eps),
//     c_ab = Kc_ab / Omega [+ Sigma_a, the change of Omega at fixed Sigma, when K(2) is in]
//     B = sum_ab c_ab / dim^2,  G_diag = (mean c_aa - mean c_{a!=b}) / 2.
// docs/stiffness.md derives both. Collective.
#include <functional>

#include "granpack/rigidity/direct_solver.h"
#include "granpack/rigidity/stiffness_system.h"

namespace granpack {

template <int dim> struct Moduli {
  Tensor<dim> schur = Tensor<dim>::Zero();     ///< C, scaled (N/m)
  Tensor<dim> stiffness = Tensor<dim>::Zero(); ///< c_ab (Pa in 3D)
  double bulk = 0;                             ///< B
  double shear_diag = 0;                       ///< G_diag
  double seconds = 0;                          ///< the dim solves and dot products
};

/// `stress`: the stress the Omega-change term uses (pass zero for K(1) alone).
/// `solve(rhs, x)`: x = K_uu^{-1} rhs (a factorisation or a preconditioned Krylov solver).
using GrainSolve = std::function<void(::Vec, ::Vec)>;

template <int dim>
Moduli<dim> condense(const BorderedMatrix<dim>& b, const GrainSolve& solve, const Vec<dim>& cell,
                     double volume, const Vec<dim>& stress);

} // namespace granpack
