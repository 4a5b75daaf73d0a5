#pragma once
// A sparse direct factorisation of the grain block through PETSc + MUMPS, with MUMPS's
// null-pivot detection (ICNTL(24)) and pivot inertia (INFOG(12), INFOG(28)). Solver options
// stay run-time options under the prefix "stiffness_" (e.g. PETSC_OPTIONS=
// "-stiffness_mat_mumps_icntl_14 50"). Collective on the matrix's communicator.
#include "granpack/rigidity/petsc_support.h"

namespace granpack {

struct DirectSolver {
  OwnedKsp ksp;
  std::int64_t null_pivots = 0;     ///< INFOG(28): pivots below the threshold
  std::int64_t negative_pivots = 0; ///< INFOG(12): negative pivots (LDLᵀ only)
  double seconds = 0;               ///< symbolic + numeric factorisation

  /// x = A^{-1} b with the factors (x and b laid out like A's rows).
  void solve(::Vec b, ::Vec x) const;
};

/// Solves with a matrix close to an already factorised one (K = K(1) + K(2) with the factors
/// of K(1)): GMRES preconditioned by those factors, to a relative residual `rtol`. K(2) is a
/// perturbation of relative size ~ h/a, so a few iterations replace a second factorisation.
struct PreconditionedSolver {
  OwnedKsp ksp;
  const DirectSolver* factors = nullptr;
  std::int64_t iterations = 0; ///< largest count over the solves so far
  /// x = A^{-1} b; throws if GMRES does not converge.
  void solve(::Vec b, ::Vec x);
};
PreconditionedSolver krylov_with_factors(Mat a, const DirectSolver& factors, double rtol);

/// Factorises `a`: LDLᵀ (symmetric `a`) or LU. A pivot is declared null when its magnitude
/// is below null_pivot_threshold x the infinity norm of the (scaled) matrix (MUMPS CNTL(3)).
DirectSolver factorize(Mat a, bool symmetric, double null_pivot_threshold);

} // namespace granpack
