#include "granpack/rigidity/direct_solver.h"

#include <algorithm>
#include <chrono>

namespace granpack {

void DirectSolver::solve(::Vec b, ::Vec x) const {
  GRANPACK_PETSC(KSPSolve(ksp, b, x));
}

namespace {
PetscErrorCode apply_factors(PC pc, ::Vec x, ::Vec y) {
  void* ctx = nullptr;
  PetscCall(PCShellGetContext(pc, &ctx));
  PetscCall(KSPSolve(static_cast<const DirectSolver*>(ctx)->ksp, x, y));
  return 0;
}
} // namespace

void PreconditionedSolver::solve(::Vec b, ::Vec x) {
  GRANPACK_PETSC(KSPSolve(ksp, b, x));
  KSPConvergedReason reason;
  GRANPACK_PETSC(KSPGetConvergedReason(ksp, &reason));
  PetscInt its = 0;
  GRANPACK_PETSC(KSPGetIterationNumber(ksp, &its));
  iterations = std::max<std::int64_t>(iterations, its);
  GRANPACK_CHECK(
      reason > 0,
      "stiffness: GMRES on K = K(1) + K(2) preconditioned by K(1) did not converge (reason "
          << reason << " after " << its << " iterations)");
}

PreconditionedSolver krylov_with_factors(Mat a, const DirectSolver& factors, double rtol) {
  MPI_Comm comm = MPI_COMM_NULL;
  GRANPACK_PETSC(PetscObjectGetComm(reinterpret_cast<PetscObject>(a), &comm));
  PreconditionedSolver s;
  s.factors = &factors;
  GRANPACK_PETSC(KSPCreate(comm, s.ksp.address()));
  GRANPACK_PETSC(KSPSetOptionsPrefix(s.ksp, "stiffness_k_"));
  GRANPACK_PETSC(KSPSetOperators(s.ksp, a, a));
  GRANPACK_PETSC(KSPSetType(s.ksp, KSPGMRES));
  GRANPACK_PETSC(KSPGMRESSetRestart(s.ksp, 100));
  GRANPACK_PETSC(KSPSetTolerances(s.ksp, rtol, 0.0, PETSC_DEFAULT, 500));
  PC pc = nullptr;
  GRANPACK_PETSC(KSPGetPC(s.ksp, &pc));
  GRANPACK_PETSC(PCSetType(pc, PCSHELL));
  GRANPACK_PETSC(PCShellSetContext(pc, const_cast<DirectSolver*>(&factors)));
  GRANPACK_PETSC(PCShellSetApply(pc, apply_factors));
  GRANPACK_PETSC(KSPSetFromOptions(s.ksp));
  GRANPACK_PETSC(KSPSetUp(s.ksp));
  return s;
}

DirectSolver factorize(Mat a, bool symmetric, double null_pivot_threshold) {
  const auto start = std::chrono::steady_clock::now();
  MPI_Comm comm = MPI_COMM_NULL;
  GRANPACK_PETSC(PetscObjectGetComm(reinterpret_cast<PetscObject>(a), &comm));
  DirectSolver s;
  GRANPACK_PETSC(KSPCreate(comm, s.ksp.address()));
  GRANPACK_PETSC(KSPSetOptionsPrefix(s.ksp, "stiffness_"));
  GRANPACK_PETSC(KSPSetOperators(s.ksp, a, a));
  GRANPACK_PETSC(KSPSetType(s.ksp, KSPPREONLY));
  PC pc = nullptr;
  GRANPACK_PETSC(KSPGetPC(s.ksp, &pc));
  if (symmetric)
    GRANPACK_PETSC(MatSetOption(a, MAT_SYMMETRIC, PETSC_TRUE));
  GRANPACK_PETSC(PCSetType(pc, symmetric ? PCCHOLESKY : PCLU));
  GRANPACK_PETSC(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS));
  GRANPACK_PETSC(PCFactorSetUpMatSolverType(pc));
  Mat f = nullptr;
  GRANPACK_PETSC(PCFactorGetMatrix(pc, &f));
  GRANPACK_PETSC(MatMumpsSetIcntl(f, 24, 1)); // detect null pivots instead of failing
  GRANPACK_PETSC(MatMumpsSetCntl(f, 3, null_pivot_threshold));
  GRANPACK_PETSC(KSPSetFromOptions(s.ksp));
  GRANPACK_PETSC(KSPSetUp(s.ksp));
  PetscInt info = 0;
  GRANPACK_PETSC(MatMumpsGetInfog(f, 1, &info));
  GRANPACK_CHECK(info >= 0, "stiffness: MUMPS factorisation failed, INFOG(1) = " << info);
  GRANPACK_PETSC(MatMumpsGetInfog(f, 28, &info));
  s.null_pivots = info;
  if (symmetric) {
    GRANPACK_PETSC(MatMumpsGetInfog(f, 12, &info));
    s.negative_pivots = info;
  }
  s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return s;
}

} // namespace granpack
