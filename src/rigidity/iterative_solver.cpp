#include "granpack/rigidity/iterative_solver.h"

#include <chrono>
#include <sstream>

namespace granpack {

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// MINRES's stopping test. PETSc's MINRES (3.18) tracks only a preconditioner-weighted
/// residual norm, which differs from |b - A x| by up to the preconditioner's condition number:
/// whenever that norm falls below the level expected to mean |b - A x| / |b| <= rtol, the true
/// residual is computed (one product with A); if it is still above rtol, the level is lowered
/// by the ratio just measured. A handful of checks per solve.
struct TrueResidualTest {
  double rtol = 0;
  double level = 0; ///< of the solver's norm; <= 0: check at the next call
  double b_norm = 0;
  OwnedVec r;
};

PetscErrorCode true_residual_test(KSP ksp, PetscInt it, PetscReal rnorm, KSPConvergedReason* reason,
                                  void* ctx) {
  auto* t = static_cast<TrueResidualTest*>(ctx);
  *reason = KSP_CONVERGED_ITERATING;
  if (PetscIsInfOrNanReal(rnorm)) {
    *reason = KSP_DIVERGED_NANORINF;
    return 0;
  }
  ::Vec b = nullptr, x = nullptr;
  PetscCall(KSPGetRhs(ksp, &b));
  if (it == 0) {
    PetscCall(VecNorm(b, NORM_2, &t->b_norm));
    if (!t->r.get())
      PetscCall(VecDuplicate(b, t->r.address()));
    t->level = 0;
  }
  if (t->level > 0 && rnorm > t->level)
    return 0;
  if (t->b_norm == 0) {
    *reason = KSP_CONVERGED_ATOL;
    return 0;
  }
  Mat a = nullptr;
  PetscCall(KSPGetOperators(ksp, &a, nullptr));
  PetscCall(KSPBuildSolution(ksp, nullptr, &x));
  PetscCall(MatMult(a, x, t->r));
  PetscCall(VecAYPX(t->r, -1.0, b));
  PetscReal r_norm = 0;
  PetscCall(VecNorm(t->r, NORM_2, &r_norm));
  const double relative = r_norm / t->b_norm;
  if (relative <= t->rtol)
    *reason = KSP_CONVERGED_RTOL;
  else
    t->level = rnorm * (t->rtol / relative);
  return 0;
}

PetscErrorCode destroy_true_residual_test(void* ctx) {
  delete static_cast<TrueResidualTest*>(ctx);
  return 0;
}

/// The Krylov method and its residual norm: CG tracks |r| itself with the norm type below;
/// GMRES preconditioned on the right minimises the true residual; MINRES (left-preconditioned
/// only) stops on the true residual through true_residual_test: all three stop on
/// |b - A x| / |b| <= rtol rather than on a norm the preconditioner has reweighted.
void configure_ksp(KSP ksp, const char* prefix, Mat a, Mat p, KrylovMethod method, double rtol,
                   int max_iterations) {
  GRANPACK_PETSC(KSPSetOptionsPrefix(ksp, prefix));
  GRANPACK_PETSC(KSPSetOperators(ksp, a, p));
  switch (method) {
  case KrylovMethod::kCg:
    GRANPACK_PETSC(KSPSetType(ksp, KSPCG));
    GRANPACK_PETSC(KSPSetNormType(ksp, KSP_NORM_UNPRECONDITIONED));
    break;
  case KrylovMethod::kMinres: {
    GRANPACK_PETSC(KSPSetType(ksp, KSPMINRES));
    auto* test = new TrueResidualTest;
    test->rtol = rtol;
    GRANPACK_PETSC(
        KSPSetConvergenceTest(ksp, true_residual_test, test, destroy_true_residual_test));
    break;
  }
  case KrylovMethod::kGmres:
    GRANPACK_PETSC(KSPSetType(ksp, KSPGMRES));
    GRANPACK_PETSC(KSPGMRESSetRestart(ksp, 200));
    GRANPACK_PETSC(KSPSetPCSide(ksp, PC_RIGHT));
    break;
  }
  GRANPACK_PETSC(KSPSetTolerances(ksp, rtol, 0.0, PETSC_DEFAULT, max_iterations));
}

void describe(IterativeSolver& s) {
  KSPType kt = nullptr;
  GRANPACK_PETSC(KSPGetType(s.ksp, &kt));
  PC pc = nullptr;
  GRANPACK_PETSC(KSPGetPC(s.ksp, &pc));
  PCType pt = nullptr;
  GRANPACK_PETSC(PCGetType(pc, &pt));
  s.method = kt ? kt : "";
  s.preconditioner = pt ? pt : "";
}

PetscErrorCode apply_shared(PC pc, ::Vec x, ::Vec y) {
  void* ctx = nullptr;
  PetscCall(PCShellGetContext(pc, &ctx));
  PetscCall(PCApply(static_cast<PC>(ctx), x, y));
  return 0;
}
PetscErrorCode apply_shared_transpose(PC pc, ::Vec x, ::Vec y) {
  void* ctx = nullptr;
  PetscCall(PCShellGetContext(pc, &ctx));
  PetscCall(PCApplyTranspose(static_cast<PC>(ctx), x, y));
  return 0;
}

} // namespace

PC IterativeSolver::pc() const {
  PC p = nullptr;
  GRANPACK_PETSC(KSPGetPC(ksp, &p));
  return p;
}

namespace {

/// |b - A x| / |b|, A the KSP's operator (or its transpose).
double true_residual(KSP ksp, ::Vec b, ::Vec x, bool transpose) {
  Mat a = nullptr;
  GRANPACK_PETSC(KSPGetOperators(ksp, &a, nullptr));
  OwnedVec r;
  GRANPACK_PETSC(VecDuplicate(b, r.address()));
  if (transpose)
    GRANPACK_PETSC(MatMultTranspose(a, x, r));
  else
    GRANPACK_PETSC(MatMult(a, x, r));
  GRANPACK_PETSC(VecAYPX(r, -1.0, b));
  PetscReal rn = 0, bn = 0;
  GRANPACK_PETSC(VecNorm(r, NORM_2, &rn));
  GRANPACK_PETSC(VecNorm(b, NORM_2, &bn));
  return bn > 0 ? rn / bn : rn;
}

/// One KSP solve from the current x; returns its reason and adds its iterations to `its`.
KSPConvergedReason solve_once(KSP ksp, ::Vec b, ::Vec x, bool transpose, std::int64_t& its) {
  if (transpose)
    GRANPACK_PETSC(KSPSolveTranspose(ksp, b, x));
  else
    GRANPACK_PETSC(KSPSolve(ksp, b, x));
  KSPConvergedReason reason;
  GRANPACK_PETSC(KSPGetConvergedReason(ksp, &reason));
  PetscInt n = 0;
  GRANPACK_PETSC(KSPGetIterationNumber(ksp, &n));
  its += n;
  return reason;
}

} // namespace

void IterativeSolver::run(::Vec b, ::Vec x, bool transpose) {
  if (!converged) { // after a failed solve the result is invalid: the others are not tried
    GRANPACK_PETSC(VecSet(x, 0.0));
    iterations.push_back(0);
    residuals.push_back(1.0);
    return;
  }
  const auto start = std::chrono::steady_clock::now();
  PetscReal rtol = 0;
  GRANPACK_PETSC(KSPGetTolerances(ksp, &rtol, nullptr, nullptr, nullptr));
  GRANPACK_PETSC(VecSet(x, 0.0));
  std::int64_t its = 0;
  KSPConvergedReason reason = solve_once(ksp, b, x, transpose, its);
  double residual = true_residual(ksp, b, x, transpose);
  // The recurrences the solvers stop on (GMRES's least-squares estimate across restarts, CG's
  // updated residual, the preconditioned norm of a transposed right-preconditioned GMRES) can
  // differ from the true residual in rounding (3e-8 for 1e-8 was met): restart from x (the
  // restart computes b - A x afresh; PETSc's default test stays relative to |b|).
  for (int k = 0; k < 3 && reason > 0 && residual > rtol; ++k) {
    GRANPACK_PETSC(KSPSetInitialGuessNonzero(ksp, PETSC_TRUE));
    reason = solve_once(ksp, b, x, transpose, its);
    GRANPACK_PETSC(KSPSetInitialGuessNonzero(ksp, PETSC_FALSE));
    residual = true_residual(ksp, b, x, transpose);
  }
  const double seconds = seconds_since(start);
  solve_seconds += seconds;
  iterations.push_back(its);
  residuals.push_back(residual);
  if (reason <= 0 && converged) {
    converged = false;
    std::ostringstream os;
    os << method << " with " << preconditioner << " stopped after " << its
       << " iterations: " << KSPConvergedReasons[reason] << ", |b - A x|/|b| = " << residual;
    failure = os.str();
  }
  if (!label.empty()) {
    MPI_Comm comm = MPI_COMM_NULL;
    GRANPACK_PETSC(PetscObjectGetComm(reinterpret_cast<PetscObject>(ksp.get()), &comm));
    GRANPACK_PETSC(PetscFPrintf(comm, PETSC_STDERR,
                                "stiffness: %s solve %zu%s: %s + %s, %lld iterations, |r|/|b| "
                                "%.3g, %.1f s\n",
                                label.c_str(), iterations.size(), transpose ? " (adjoint)" : "",
                                method.c_str(), preconditioner.c_str(), static_cast<long long>(its),
                                residual, seconds));
  }
}

void IterativeSolver::solve(::Vec b, ::Vec x) {
  run(b, x, false);
}

void IterativeSolver::solve_transpose(::Vec b, ::Vec x) {
  run(b, x, true);
}

IterativeSolver iterative_solver(Mat a, Mat amg_matrix, MatNullSpace near_null, KrylovMethod method,
                                 double rtol, int max_iterations) {
  MPI_Comm comm = MPI_COMM_NULL;
  GRANPACK_PETSC(PetscObjectGetComm(reinterpret_cast<PetscObject>(a), &comm));
  const auto start = std::chrono::steady_clock::now();
  IterativeSolver s;
  GRANPACK_PETSC(KSPCreate(comm, s.ksp.address()));
  // GAMG aggregates grains (the block size) and interpolates the rigid-body modes; told the
  // matrix is symmetric, it does not symmetrise the graph.
  GRANPACK_PETSC(MatSetOption(amg_matrix, MAT_SYMMETRIC, PETSC_TRUE));
  GRANPACK_PETSC(MatSetNearNullSpace(amg_matrix, near_null));
  configure_ksp(s.ksp, "stiffness_krylov_", a, amg_matrix, method, rtol, max_iterations);
  PC pc = nullptr;
  GRANPACK_PETSC(KSPGetPC(s.ksp, &pc));
  GRANPACK_PETSC(PCSetType(pc, PCGAMG));
  GRANPACK_PETSC(KSPSetFromOptions(s.ksp));
  GRANPACK_PETSC(KSPSetUp(s.ksp));
  describe(s);
  s.setup_seconds = seconds_since(start);
  return s;
}

IterativeSolver iterative_solver_sharing(Mat a, const IterativeSolver& other, KrylovMethod method,
                                         double rtol, int max_iterations) {
  MPI_Comm comm = MPI_COMM_NULL;
  GRANPACK_PETSC(PetscObjectGetComm(reinterpret_cast<PetscObject>(a), &comm));
  IterativeSolver s;
  GRANPACK_PETSC(KSPCreate(comm, s.ksp.address()));
  // Its own prefix: a user's -stiffness_krylov_pc_type must not replace the shell.
  configure_ksp(s.ksp, "stiffness_krylov_shared_", a, a, method, rtol, max_iterations);
  PC pc = nullptr;
  GRANPACK_PETSC(KSPGetPC(s.ksp, &pc));
  GRANPACK_PETSC(PCSetType(pc, PCSHELL));
  GRANPACK_PETSC(PCShellSetContext(pc, other.pc()));
  GRANPACK_PETSC(PCShellSetApply(pc, apply_shared));
  GRANPACK_PETSC(PCShellSetApplyTranspose(pc, apply_shared_transpose));
  GRANPACK_PETSC(PCShellSetName(pc, ("shared " + other.preconditioner).c_str()));
  GRANPACK_PETSC(KSPSetFromOptions(s.ksp));
  GRANPACK_PETSC(KSPSetUp(s.ksp));
  describe(s);
  s.preconditioner = "shared " + other.preconditioner;
  return s;
}

} // namespace granpack
