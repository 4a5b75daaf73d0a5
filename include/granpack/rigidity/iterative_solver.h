#pragma once
// A preconditioned Krylov solver for the grain block, for packings whose sparse
// factorisation does not fit (docs/stiffness.md, "Moduli of large packings"): conjugate
// gradients for a symmetric positive-definite block, MINRES for a symmetric one that may be
// indefinite, GMRES (right-preconditioned) otherwise, with an algebraic multigrid (PCGAMG)
// built on a symmetric positive-definite matrix and told the rigid-body near-null space
// (rigidity/rigid_body_modes.h). Tolerances are on the true residual |b - A x| / |b|. Solver
// choices stay run-time options under the prefix "stiffness_krylov_" (e.g.
// PETSC_OPTIONS="-stiffness_krylov_pc_type hypre"; "stiffness_krylov_shared_" for the solver that
// borrows another's multigrid). Collective on the matrix's communicator.
#include <cstdint>
#include <string>
#include <vector>

#include "granpack/rigidity/petsc_support.h"

namespace granpack {

/// cg: symmetric positive definite (operator and preconditioner); minres: symmetric operator,
/// possibly indefinite, symmetric positive-definite preconditioner (left, its own norm: the
/// stopping test checks |b - A x| / |b| whenever that norm says rtol is reached, and tightens
/// until it is); gmres: any.
enum class KrylovMethod { kCg, kMinres, kGmres };

struct IterativeSolver {
  OwnedKsp ksp;
  std::string method;                   ///< KSP type that ran ("cg", "minres", "gmres")
  std::string preconditioner;           ///< PC type ("gamg", or "shell" for another's AMG)
  std::vector<std::int64_t> iterations; ///< per solve, in order (restarts included)
  /// |b - A x| / |b| per solve, recomputed after it; a solve whose recurrence stopped while
  /// this was still above rtol is restarted from x (up to 3 times).
  std::vector<double> residuals;
  double setup_seconds = 0; ///< the multigrid hierarchy
  double solve_seconds = 0; ///< every solve so far
  /// False once a solve has stopped short of rtol (iteration limit, breakdown, an indefinite
  /// matrix under CG): `failure` says how. Not thrown, so that what was reached is reported;
  /// the later solves are skipped (x = 0, 0 iterations, residual 1).
  bool converged = true;
  std::string failure;
  /// With a label, each solve is logged on the communicator's rank 0 (stderr) as it ends: a
  /// solve on 256 000 grains takes minutes, and a run stopped early then shows how far it got.
  std::string label;

  /// x = A^{-1} b from x = 0.
  void solve(::Vec b, ::Vec x);
  /// x = A^{-T} b (the adjoint of a non-symmetric block), the same preconditioner transposed.
  void solve_transpose(::Vec b, ::Vec x);
  /// The preconditioner, to be shared by another solver (iterative_solver_sharing()).
  PC pc() const;

private:
  void run(::Vec b, ::Vec x, bool transpose);
};

/// `a` the operator; `amg_matrix` the symmetric positive-definite matrix the multigrid is
/// built on (`a` itself when it is symmetric positive definite); `near_null` its rigid-body
/// modes.
IterativeSolver iterative_solver(Mat a, Mat amg_matrix, MatNullSpace near_null, KrylovMethod method,
                                 double rtol, int max_iterations);

/// A solver for `a` preconditioned by another solver's multigrid (set up once): for K =
/// K(1) + K(2), by K(1)'s multigrid (positive definite by construction): with friction K's
/// non-symmetric part is a perturbation of size h/a (GMRES); without, K is symmetric but K(2)
/// may make it indefinite (MINRES). `other` must outlive the returned solver.
IterativeSolver iterative_solver_sharing(Mat a, const IterativeSolver& other, KrylovMethod method,
                                         double rtol, int max_iterations);

} // namespace granpack
