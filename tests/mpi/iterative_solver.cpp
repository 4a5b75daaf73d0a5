// The Krylov solvers of the "Moduli of large packings" path (rigidity/iterative_solver.h) on a
// matrix small enough to check by hand, whose grain block has the structure of a stiffness
// matrix: 3 unknowns per node, nodes on a ring joined by springs of stiffness 1 (three 1D
// periodic Laplacians, eigenvalues 2 (1 - cos(2 pi m / N)), each threefold), a ground spring
// delta on every unknown. Two operators:
//  - P = L + delta 1, symmetric positive definite: CG with the multigrid built on it;
//  - A = P - sigma 1 with sigma between eigenvalues, symmetric and indefinite (as K(1) + K(2)
//    can be without friction): MINRES preconditioned by P's multigrid (shared, not rebuilt).
// Checked: both solves stop on the true residual |b - A x| / |b| <= rtol (recomputed here,
// independently of the solver's report; PETSc's MINRES tracks only a preconditioner-weighted
// norm, which the stopping test must translate), x agrees with the exact solution of the
// 1D problem by Fourier modes within cond x rtol, and the JSON-facing names are the methods
// that ran. A stopping test on the weighted norm alone, or a shared preconditioner that is not
// P's, fails the residual or the name checks. Every rank.
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "granpack/rigidity/iterative_solver.h"
#include "granpack/rigidity/petsc_support.h"

using namespace granpack;

namespace {

constexpr PetscInt kNodes = 600;
constexpr PetscInt kBlock = 3;
constexpr double kDelta = 1e-3;

double ring_eigenvalue(PetscInt m) {
  return 2.0 * (1.0 - std::cos(2.0 * std::numbers::pi * static_cast<double>(m) / kNodes));
}

/// L + (delta - sigma) 1, block size 3, rows split evenly over the ranks.
OwnedMat ring_matrix(double sigma) {
  OwnedMat a;
  GRANPACK_PETSC(MatCreate(PETSC_COMM_WORLD, a.address()));
  GRANPACK_PETSC(MatSetSizes(a, PETSC_DECIDE, PETSC_DECIDE, kNodes * kBlock, kNodes * kBlock));
  GRANPACK_PETSC(MatSetType(a, MATAIJ));
  GRANPACK_PETSC(MatSetBlockSize(a, kBlock));
  GRANPACK_PETSC(MatSeqAIJSetPreallocation(a, 3, nullptr));
  GRANPACK_PETSC(MatMPIAIJSetPreallocation(a, 3, nullptr, 2, nullptr));
  PetscInt lo = 0, hi = 0;
  GRANPACK_PETSC(MatGetOwnershipRange(a, &lo, &hi));
  for (PetscInt row = lo; row < hi; ++row) {
    const PetscInt node = row / kBlock, c = row % kBlock;
    const PetscInt cols[3] = {((node + kNodes - 1) % kNodes) * kBlock + c, row,
                              ((node + 1) % kNodes) * kBlock + c};
    const PetscScalar vals[3] = {-1.0, 2.0 + kDelta - sigma, -1.0};
    GRANPACK_PETSC(MatSetValues(a, 1, &row, 3, cols, vals, INSERT_VALUES));
  }
  GRANPACK_PETSC(MatAssemblyBegin(a, MAT_FINAL_ASSEMBLY));
  GRANPACK_PETSC(MatAssemblyEnd(a, MAT_FINAL_ASSEMBLY));
  return a;
}

/// The three translations (one per component): the near-null space of L.
OwnedNullSpace translations(Mat a) {
  std::vector<OwnedVec> t(kBlock);
  std::vector<::Vec> raw;
  for (PetscInt c = 0; c < kBlock; ++c) {
    GRANPACK_PETSC(MatCreateVecs(a, t[c].address(), nullptr));
    PetscInt lo = 0, hi = 0;
    GRANPACK_PETSC(VecGetOwnershipRange(t[c], &lo, &hi));
    for (PetscInt row = lo; row < hi; ++row)
      GRANPACK_PETSC(VecSetValue(t[c], row, row % kBlock == c ? 1.0 : 0.0, INSERT_VALUES));
    GRANPACK_PETSC(VecAssemblyBegin(t[c]));
    GRANPACK_PETSC(VecAssemblyEnd(t[c]));
    GRANPACK_PETSC(VecNormalize(t[c], nullptr));
    raw.push_back(t[c]);
  }
  OwnedNullSpace ns;
  GRANPACK_PETSC(
      MatNullSpaceCreate(PETSC_COMM_WORLD, PETSC_FALSE, kBlock, raw.data(), ns.address()));
  return ns;
}

/// b: component c of node i is cos(2 pi k (i + c) / N) for one wave number k, so that the
/// exact solution is b / (lambda_k + delta - sigma).
void wave(::Vec b, PetscInt k) {
  PetscInt lo = 0, hi = 0;
  GRANPACK_PETSC(VecGetOwnershipRange(b, &lo, &hi));
  for (PetscInt row = lo; row < hi; ++row) {
    const PetscInt node = row / kBlock, c = row % kBlock;
    GRANPACK_PETSC(VecSetValue(
        b, row, std::cos(2.0 * std::numbers::pi * static_cast<double>(k * (node + c)) / kNodes),
        INSERT_VALUES));
  }
  GRANPACK_PETSC(VecAssemblyBegin(b));
  GRANPACK_PETSC(VecAssemblyEnd(b));
}

double relative_residual(Mat a, ::Vec b, ::Vec x) {
  OwnedVec r;
  GRANPACK_PETSC(VecDuplicate(b, r.address()));
  GRANPACK_PETSC(MatMult(a, x, r));
  GRANPACK_PETSC(VecAYPX(r, -1.0, b));
  PetscReal rn = 0, bn = 0;
  GRANPACK_PETSC(VecNorm(r, NORM_2, &rn));
  GRANPACK_PETSC(VecNorm(b, NORM_2, &bn));
  return rn / bn;
}

/// |x - b / d| / |b / d|.
double error_against(::Vec x, ::Vec b, double d) {
  OwnedVec e;
  GRANPACK_PETSC(VecDuplicate(b, e.address()));
  GRANPACK_PETSC(VecCopy(b, e));
  GRANPACK_PETSC(VecScale(e, 1.0 / d));
  PetscReal top = 0, diff = 0;
  GRANPACK_PETSC(VecNorm(e, NORM_2, &top));
  GRANPACK_PETSC(VecAXPY(e, -1.0, x));
  GRANPACK_PETSC(VecNorm(e, NORM_2, &diff));
  return diff / top;
}

} // namespace

TEST(IterativeSolver, MinresWithSharedMultigridSolvesAnIndefiniteBlock) {
  ensure_petsc_initialized();
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  constexpr double rtol = 1e-8;
  // sigma halfway between the eigenvalues of wave numbers 3 and 4: 6 x 3 + 3 = 21 of A's
  // 1800 eigenvalues are negative, the smallest |eigenvalue| 3.8e-4 (cond 1e4).
  const double sigma = 0.5 * (ring_eigenvalue(3) + ring_eigenvalue(4)) + kDelta;
  const OwnedMat p = ring_matrix(0.0);
  const OwnedMat a = ring_matrix(sigma);
  const OwnedNullSpace ns = translations(p);

  IterativeSolver spd = iterative_solver(p, p, ns, KrylovMethod::kCg, rtol, 5000);
  IterativeSolver indefinite = iterative_solver_sharing(a, spd, KrylovMethod::kMinres, rtol, 5000);
  EXPECT_EQ(spd.method, "cg");
  EXPECT_EQ(spd.preconditioner, "gamg");
  EXPECT_EQ(indefinite.method, "minres");
  EXPECT_EQ(indefinite.preconditioner, "shared gamg");

  OwnedVec b, x;
  GRANPACK_PETSC(MatCreateVecs(p, x.address(), b.address()));
  for (const PetscInt k : {PetscInt{1}, PetscInt{3}, PetscInt{4}, PetscInt{40}}) {
    wave(b, k);
    spd.solve(b, x);
    const double res_p = relative_residual(p, b, x);
    const double err_p = error_against(x, b, ring_eigenvalue(k) + kDelta);
    indefinite.solve(b, x);
    const double res_a = relative_residual(a, b, x);
    const double d = ring_eigenvalue(k) + kDelta - sigma;
    const double err_a = error_against(x, b, d);
    EXPECT_LE(res_p, rtol) << "k = " << k;
    EXPECT_LE(res_a, rtol) << "k = " << k;
    // The solves' own record of the true residual is this one.
    EXPECT_NEAR(indefinite.residuals.back(), res_a, 1e-3 * rtol) << "k = " << k;
    // |x - x*| / |x*| <= |d| / min|eigenvalue| x |r| / |b|: delta for P, 3.8e-4 for A.
    EXPECT_LT(err_p, (ring_eigenvalue(k) + kDelta) / kDelta * rtol) << "k = " << k;
    EXPECT_LT(err_a, std::abs(d) / 3.8e-4 * rtol) << "k = " << k;
    if (rank == 0)
      std::printf("[ iterative ] k = %lld (A's eigenvalue %+.3g): CG on P %lld its, |r|/|b| "
                  "%.2g, error %.2g; MINRES on A %lld its, |r|/|b| %.2g, error %.2g\n",
                  static_cast<long long>(k), d, static_cast<long long>(spd.iterations.back()),
                  res_p, err_p, static_cast<long long>(indefinite.iterations.back()), res_a, err_a);
  }
  EXPECT_TRUE(spd.converged) << spd.failure;
  EXPECT_TRUE(indefinite.converged) << indefinite.failure;
}
