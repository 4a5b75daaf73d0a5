#pragma once
// Elimination of the grain unknowns onto the strain coordinates: the Schur complement
//     C = K_ee - K_eu K_uu^{-1} K_ue      (nv x nv, every strain in Voigt order, in the
//                                         scaled unknowns e_I = gamma_I s_I)
// with one factorisation of K_uu and nv solves. Then the macroscopic stiffness: with
// Kc = S C S (physical, Delta(Omega sigma_I) = Kc_IJ gamma_J, S = diag(s_I)),
//     c_IJ = Kc_IJ / Omega [+ sigma_I for a diagonal J, the change of Omega at fixed sigma,
//            when K(2) is in],
// its affine part (K_ee alone, the grains following the strain) and, from the diagonal
// block, [AR]'s B = sum_ab c_ab / dim^2 and G_diag = (mean c_aa - mean c_{a!=b}) / 2.
// docs/stiffness.md derives them. Collective.
#include <functional>

#include "granpack/rigidity/direct_solver.h"
#include "granpack/rigidity/stiffness_system.h"

namespace granpack {

template <int dim> struct Moduli {
  VoigtMatrix<dim> schur = VoigtMatrix<dim>::Zero();  ///< C, scaled (N/m), every strain
  VoigtMatrix<dim> tensor = VoigtMatrix<dim>::Zero(); ///< c_IJ (Pa in 3D, N/m in 2D)
  VoigtMatrix<dim> affine = VoigtMatrix<dim>::Zero(); ///< c_IJ of K_ee alone (affine motion)
  Tensor<dim> stiffness = Tensor<dim>::Zero();        ///< c_ab, the diagonal strains' block
  double bulk = 0;                                    ///< B
  double shear_diag = 0;                              ///< G_diag
  double seconds = 0;                                 ///< the nv solves and dot products

  /// The diagonal strains' Schur complement ([AR]'s dim strain unknowns).
  Tensor<dim> diagonal_schur() const { return schur.template topLeftCorner<dim, dim>(); }
};

/// `stress`: sigma_I, the stress the Omega-change term uses (pass zero for K(1) alone).
/// `solve(rhs, x)`: x = K_uu^{-1} rhs (a factorisation or a preconditioned Krylov solver).
using GrainSolve = std::function<void(::Vec, ::Vec)>;

template <int dim>
Moduli<dim> condense(const BorderedMatrix<dim>& b, const GrainSolve& solve,
                     const RigidityLayout<dim>& layout, double volume, const VoigtVec<dim>& stress);

/// The same from approximate solves (an iterative solver stopped at a relative residual
/// rtol): C_IJ = K_ee - (K_eu,I . x_J + y_I . r_J) with x_J ~ K_uu^{-1} K_ue,J, its residual
/// r_J = K_ue,J - K_uu x_J and y_I ~ K_uu^{-T} K_eu,I (`adjoint`; empty when K_uu and its
/// border are symmetric, y = x). The error is -(y - y*)ᵀ K_uu (x - x*), second order in the
/// solves' errors: of order rtol² cond(K_uu) relative, where the plain formula would be off by
/// rtol cond(K_uu) — which matters for nearly isostatic packings (cond ~ 1e6).
template <int dim>
Moduli<dim> condense_approximately(const BorderedMatrix<dim>& b, const GrainSolve& solve,
                                   const GrainSolve& adjoint, const RigidityLayout<dim>& layout,
                                   double volume, const VoigtVec<dim>& stress);

} // namespace granpack
