#include "granpack/rigidity/direct_solver.h"

#include <algorithm>
#include <chrono>
#include <optional>
#include <string>

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

namespace {
/// Sets a PETSc run-time option for the lifetime of this object, then restores what was
/// there (the user's value, or nothing).
class ScopedOption {
public:
  ScopedOption(const char* name, const std::string& value) : name_(name) {
    char previous[256] = "";
    PetscBool set = PETSC_FALSE;
    GRANPACK_PETSC(PetscOptionsGetString(nullptr, nullptr, name, previous, sizeof previous, &set));
    if (set)
      previous_ = previous;
    GRANPACK_PETSC(PetscOptionsSetValue(nullptr, name, value.c_str()));
  }
  ScopedOption(const ScopedOption&) = delete;
  ScopedOption& operator=(const ScopedOption&) = delete;
  ~ScopedOption() {
    if (previous_)
      PetscOptionsSetValue(nullptr, name_, previous_->c_str());
    else
      PetscOptionsClearValue(nullptr, name_);
  }

private:
  const char* name_;
  std::optional<std::string> previous_;
};

/// One factorisation attempt; INFOG(1) and the ICNTL(14) used (MUMPS's extra workspace over
/// its analysis's estimate, in %) are returned in `info` and `percent_used`.
DirectSolver attempt(Mat a, bool symmetric, double null_pivot_threshold, PetscInt& info,
                     PetscInt& percent_used) {
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
  GRANPACK_PETSC(MatMumpsGetIcntl(f, 14, &percent_used));
  GRANPACK_PETSC(MatMumpsGetInfog(f, 1, &info));
  if (info < 0)
    return s;
  PetscInt value = 0;
  GRANPACK_PETSC(MatMumpsGetInfog(f, 28, &value));
  s.null_pivots = value;
  if (symmetric) {
    GRANPACK_PETSC(MatMumpsGetInfog(f, 12, &value));
    s.negative_pivots = value;
  }
  return s;
}
} // namespace

DirectSolver factorize(Mat a, bool symmetric, double null_pivot_threshold) {
  const auto start = std::chrono::steady_clock::now();
  // MUMPS sizes its workspace from the analysis; null and delayed pivots (the singular K(1) of
  // a crystal, the mechanisms of a loose packing) can need more than that estimate, and how
  // much more depends on the parallel ordering, which varies between runs on 3 or more ranks
  // (INFOG(1) = -9 in 2 of 8 runs of the FCC crystal on 4 ranks). MUMPS's remedy for -8, -9,
  // -11 and -12 (workspace too small) is a larger ICNTL(14) and a new factorisation: up to
  // three more attempts, the extra workspace four times larger each time.
  PetscInt info = 0, percent = 0;
  DirectSolver s = attempt(a, symmetric, null_pivot_threshold, info, percent);
  for (int retry = 0; retry < 3 && (info == -8 || info == -9 || info == -11 || info == -12);
       ++retry) {
    // Through the options database, where PETSc reads ICNTL(14) at the factorisation (a value
    // set on the factor before would be overwritten by a run-time option of the user's).
    const ScopedOption larger("-stiffness_mat_mumps_icntl_14",
                              std::to_string(4 * std::max<PetscInt>(percent, 20)));
    s = attempt(a, symmetric, null_pivot_threshold, info, percent);
  }
  GRANPACK_CHECK(info >= 0, "stiffness: MUMPS factorisation failed, INFOG(1) = "
                                << info << " (with ICNTL(14) = " << percent
                                << " % extra workspace)");
  s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return s;
}

} // namespace granpack
