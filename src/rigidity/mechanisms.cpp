#include "granpack/rigidity/mechanisms.h"

#include <slepceps.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <set>

namespace granpack {

namespace {

/// The grain's rows in K_uu.
std::vector<PetscInt> grain_rows(std::int64_t index, int g) {
  std::vector<PetscInt> rows(g);
  for (int d = 0; d < g; ++d) rows[d] = PetscInt(index * g + d);
  return rows;
}

/// Pins grain `index`'s translations in `b` (rows, columns and border entries).
template <int dim> void pin(BorderedMatrix<dim>& b, std::int64_t index, int g, bool owner, double diagonal) {
  std::vector<PetscInt> rows = grain_rows(index, g);
  rows.resize(dim);
  const PetscInt n = owner ? dim : 0;
  GRANPACK_PETSC(MatZeroRowsColumns(b.uu, n, rows.data(), diagonal, nullptr, nullptr));
  const std::vector<PetscScalar> zero(dim, 0.0);
  for (int a = 0; a < dim; ++a)
    for (::Vec x : {b.ue[a].get(), b.eu[a].get()}) {
      GRANPACK_PETSC(VecSetValues(x, n, rows.data(), zero.data(), INSERT_VALUES));
      GRANPACK_PETSC(VecAssemblyBegin(x));
      GRANPACK_PETSC(VecAssemblyEnd(x));
    }
}

struct ShellContext {
  const DirectSolver* solver;
};

PetscErrorCode apply_inverse(Mat shell, ::Vec x, ::Vec y) {
  ShellContext* ctx = nullptr;
  PetscCall(MatShellGetContext(shell, &ctx));
  PetscCall(KSPSolve(ctx->solver->ksp, x, y));
  return 0;
}

}  // namespace

template <int dim> KnownMechanisms remove_known_mechanisms(StiffnessSystem<dim>& s) {
  KnownMechanisms km;
  const auto& num = s.numbering;
  const int g = s.grain_dofs();
  const double kbar = s.mean_kn;

  // Rolling modes of the divalent grains (records come in pairs per grain, sorted).
  OwnedVec modes;
  GRANPACK_PETSC(MatCreateVecs(s.k1.uu, modes.address(), nullptr));
  GRANPACK_PETSC(VecSet(modes, 0.0));
  std::vector<std::pair<std::int64_t, Eigen::Matrix<double, 6, 1>>> rolling;
  std::set<std::int64_t> divalent_index;
  for (std::size_t k = 0; k + 1 < s.divalent.size(); k += 2) {
    const auto& c1 = s.divalent[k];
    const auto& c2 = s.divalent[k + 1];
    GRANPACK_CHECK(c1.grain == c2.grain && (k + 2 >= s.divalent.size() || s.divalent[k + 2].grain != c1.grain),
                   "stiffness: divalent grain " << c1.grain << " does not have exactly two backbone contacts");
    km.divalent.push_back({c1.grain, {c1.neighbour, c2.neighbour}});
    const std::int64_t index = num.index.at(c1.grain);
    divalent_index.insert(index);
    const Vec<3> p1(c1.branch[0], c1.branch[1], c1.branch[2]), p2(c2.branch[0], c2.branch[1], c2.branch[2]);
    rolling.emplace_back(index, divalent_rolling_mode(p1, p2, s.layout.ell));
  }
  GRANPACK_CHECK(s.divalent.size() % 2 == 0, "stiffness: odd number of divalent contact records");
  for (const auto& [index, v] : rolling)
    if (index >= num.first && index < num.first + num.local) {
      const auto rows = grain_rows(index, g);
      GRANPACK_PETSC(VecSetValues(modes, g, rows.data(), v.data(), INSERT_VALUES));
    }
  GRANPACK_PETSC(VecAssemblyBegin(modes));
  GRANPACK_PETSC(VecAssemblyEnd(modes));
  if (!rolling.empty()) {
    OwnedVec image;
    GRANPACK_PETSC(VecDuplicate(modes, image.address()));
    GRANPACK_PETSC(MatMult(s.k1.uu, modes, image));
    PetscReal r = 0, m = 0, border = 0;
    GRANPACK_PETSC(VecNorm(image, NORM_2, &r));
    GRANPACK_PETSC(VecNorm(modes, NORM_2, &m));
    for (int a = 0; a < dim; ++a) {
      PetscScalar dot = 0;
      GRANPACK_PETSC(VecDot(s.k1.eu[a], modes, &dot));
      border += dot * dot;
    }
    km.divalent_residual = std::sqrt(r * r + border) / (kbar * m);
  }
  // Stiffen: <k_n> v vᵀ on each divalent grain's diagonal block (rows owned here).
  for (BorderedMatrix<dim>* b : {&s.k1, &s.k}) {
    for (const auto& [index, v] : rolling)
      if (index >= num.first && index < num.first + num.local) {
        const auto rows = grain_rows(index, g);
        const Eigen::Matrix<double, 6, 6, Eigen::RowMajor> vv = kbar * v * v.transpose();
        GRANPACK_PETSC(MatSetValues(b->uu, g, rows.data(), g, rows.data(), vv.data(), ADD_VALUES));
      }
    GRANPACK_PETSC(MatAssemblyBegin(b->uu, MAT_FINAL_ASSEMBLY));
    GRANPACK_PETSC(MatAssemblyEnd(b->uu, MAT_FINAL_ASSEMBLY));
  }

  // Pin the first grain (in the numbering) that is not divalent.
  std::int64_t pinned = 0;
  while (divalent_index.count(pinned)) ++pinned;
  GRANPACK_CHECK(pinned < num.grains, "stiffness: the backbone is empty");
  km.pinned_grain = num.ids[pinned];
  const bool owner = pinned >= num.first && pinned < num.first + num.local;
  pin(s.k1, pinned, g, owner, kbar);
  pin(s.k, pinned, g, owner, kbar);
  return km;
}

std::vector<double> smallest_eigenvalues(Mat a, const DirectSolver& solver, int count, double scale,
                                         double* seconds) {
  const auto start = std::chrono::steady_clock::now();
  MPI_Comm comm = MPI_COMM_NULL;
  GRANPACK_PETSC(PetscObjectGetComm(reinterpret_cast<PetscObject>(a), &comm));
  PetscInt m = 0, n = 0, big_m = 0, big_n = 0;
  GRANPACK_PETSC(MatGetLocalSize(a, &m, &n));
  GRANPACK_PETSC(MatGetSize(a, &big_m, &big_n));
  count = std::min<int>(count, int(big_m));
  ShellContext ctx{&solver};
  OwnedMat inverse;
  GRANPACK_PETSC(MatCreateShell(comm, m, n, big_m, big_n, &ctx, inverse.address()));
  GRANPACK_PETSC(MatShellSetOperation(inverse, MATOP_MULT, reinterpret_cast<void (*)(void)>(apply_inverse)));
  EPS eps = nullptr;
  GRANPACK_PETSC(EPSCreate(comm, &eps));
  std::vector<double> out;
  try {
    GRANPACK_PETSC(EPSSetOptionsPrefix(eps, "stiffness_"));
    GRANPACK_PETSC(EPSSetOperators(eps, inverse, nullptr));
    GRANPACK_PETSC(EPSSetProblemType(eps, EPS_HEP));
    GRANPACK_PETSC(EPSSetWhichEigenpairs(eps, EPS_LARGEST_MAGNITUDE));
    GRANPACK_PETSC(EPSSetDimensions(eps, count, PETSC_DEFAULT, PETSC_DEFAULT));
    GRANPACK_PETSC(EPSSetTolerances(eps, 1e-10, 1000));
    GRANPACK_PETSC(EPSSetFromOptions(eps));
    GRANPACK_PETSC(EPSSolve(eps));
    PetscInt converged = 0;
    GRANPACK_PETSC(EPSGetConverged(eps, &converged));
    for (PetscInt k = 0; k < std::min<PetscInt>(converged, count); ++k) {
      PetscScalar mu = 0;
      GRANPACK_PETSC(EPSGetEigenvalue(eps, k, &mu, nullptr));
      out.push_back(1.0 / (mu * scale));
    }
  } catch (...) {
    EPSDestroy(&eps);
    throw;
  }
  EPSDestroy(&eps);
  std::sort(out.begin(), out.end());
  if (seconds) *seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

template KnownMechanisms remove_known_mechanisms<2>(StiffnessSystem<2>&);
template KnownMechanisms remove_known_mechanisms<3>(StiffnessSystem<3>&);

}  // namespace granpack
