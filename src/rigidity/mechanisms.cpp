#include "granpack/rigidity/mechanisms.h"

#include <slepceps.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <set>

#include "granpack/comm/allgather.h"
#include "granpack/comm/gather.h"

namespace granpack {

namespace {

/// The grain's rows in K_uu.
std::vector<PetscInt> grain_rows(std::int64_t index, int g) {
  std::vector<PetscInt> rows(g);
  for (int d = 0; d < g; ++d)
    rows[d] = PetscInt(index * g + d);
  return rows;
}

/// Pins grain `index`'s translations in `b` (rows, columns and border entries).
template <int dim>
void pin(BorderedMatrix<dim>& b, std::int64_t index, int g, bool owner, double diagonal) {
  std::vector<PetscInt> rows = grain_rows(index, g);
  rows.resize(dim);
  const PetscInt n = owner ? dim : 0;
  GRANPACK_PETSC(MatZeroRowsColumns(b.uu, n, rows.data(), diagonal, nullptr, nullptr));
  const std::vector<PetscScalar> zero(dim, 0.0);
  for (int a = 0; a < voigt_size<dim>; ++a)
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

/// |K(1) V| / (<k_n> |V|) with the border rows, V the sum of the known modes (0 if none;
/// nested parts share grains, so the modes are added): they must be null vectors of G, so a
/// few 1e-16 is expected. Collective.
template <int dim>
double known_mode_residual(
    StiffnessSystem<dim>& s,
    const std::vector<std::pair<std::int64_t, Eigen::Matrix<double, 6, 1>>>& known) {
  const auto& num = s.numbering;
  OwnedVec modes;
  GRANPACK_PETSC(MatCreateVecs(s.k1.uu, modes.address(), nullptr));
  GRANPACK_PETSC(VecSet(modes, 0.0));
  for (const auto& [index, v] : known)
    if (index >= num.first && index < num.first + num.local) {
      const auto rows = grain_rows(index, s.grain_dofs());
      GRANPACK_PETSC(VecSetValues(modes, s.grain_dofs(), rows.data(), v.data(), ADD_VALUES));
    }
  GRANPACK_PETSC(VecAssemblyBegin(modes));
  GRANPACK_PETSC(VecAssemblyEnd(modes));
  if (known.empty()) // the same on every rank: the records are everyone's
    return 0;
  OwnedVec image;
  GRANPACK_PETSC(VecDuplicate(modes, image.address()));
  GRANPACK_PETSC(MatMult(s.k1.uu, modes, image));
  PetscReal r = 0, m = 0, border = 0;
  GRANPACK_PETSC(VecNorm(image, NORM_2, &r));
  GRANPACK_PETSC(VecNorm(modes, NORM_2, &m));
  for (int a = 0; a < voigt_size<dim>; ++a) {
    PetscScalar dot = 0;
    GRANPACK_PETSC(VecDot(s.k1.eu[a], modes, &dot));
    border += dot * dot;
  }
  return std::sqrt(r * r + border) / (s.mean_kn * m);
}

} // namespace

template <int dim> KnownMechanisms remove_known_mechanisms(StiffnessSystem<dim>& s) {
  KnownMechanisms km;
  const auto& num = s.numbering;
  const int g = s.grain_dofs();
  const double kbar = s.mean_kn;

  // Rolling modes of the divalent grains (records come in pairs per grain, sorted).
  std::vector<std::pair<std::int64_t, Eigen::Matrix<double, 6, 1>>> rolling;
  std::set<std::int64_t> divalent_index;
  for (std::size_t k = 0; k + 1 < s.divalent.size(); k += 2) {
    const auto& c1 = s.divalent[k];
    const auto& c2 = s.divalent[k + 1];
    GRANPACK_CHECK(
        c1.grain == c2.grain && (k + 2 >= s.divalent.size() || s.divalent[k + 2].grain != c1.grain),
        "stiffness: divalent grain " << c1.grain << " does not have exactly two backbone contacts");
    km.divalent.push_back({c1.grain, {c1.neighbour, c2.neighbour}});
    const std::int64_t index = num.index.at(c1.grain);
    divalent_index.insert(index);
    const Vec<3> p1(c1.branch[0], c1.branch[1], c1.branch[2]),
        p2(c2.branch[0], c2.branch[1], c2.branch[2]);
    rolling.emplace_back(index, divalent_rolling_mode(p1, p2, s.layout.ell));
  }
  GRANPACK_CHECK(s.divalent.size() % 2 == 0, "stiffness: odd number of divalent contact records");
  km.divalent_residual = known_mode_residual(s, rolling);
  // Pivoting of the parts hanging from one contact (3D, rolling resistance): each mode spans
  // its part's grains, so it is checked as one vector and stiffened where the part hinges: a
  // pivoting spring <k_n> (n.(ρ_a - ρ_b))² on the hinge contact, whose entries exist. As G v
  // = 0, K(1)'s response to the strains is unchanged (the spring only fixes the free angle).
  std::vector<std::pair<std::int64_t, Eigen::Matrix<double, 6, 1>>> pivots;
  for (const auto& c : s.pivoting) {
    km.pivoting.push_back({c.grain, {c.neighbour, std::int64_t(c.mode.size())}});
    for (const auto& [id, v] : c.mode) {
      divalent_index.insert(num.index.at(id)); // not to be pinned either
      pivots.emplace_back(num.index.at(id), v);
    }
  }
  km.pivoting_residual = known_mode_residual(s, pivots);
  // Stiffen: <k_n> v vᵀ on each divalent or pivoting grain's diagonal block (rows owned here).
  std::vector<BorderedMatrix<dim>*> matrices = {&s.k1, &s.k};
  if (s.has_gram())
    matrices.push_back(&s.gram);
  for (BorderedMatrix<dim>* b : matrices) {
    for (const auto& [index, v] : rolling)
      if (index >= num.first && index < num.first + num.local) {
        const auto rows = grain_rows(index, g);
        const Eigen::Matrix<double, 6, 6, Eigen::RowMajor> vv = kbar * v * v.transpose();
        GRANPACK_PETSC(MatSetValues(b->uu, g, rows.data(), g, rows.data(), vv.data(), ADD_VALUES));
      }
    for (const auto& c : s.pivoting) {
      const std::int64_t a = num.index.at(c.grain), n = num.index.at(c.neighbour);
      if (a < num.first || a >= num.first + num.local)
        continue; // added once, by the hinge grain's owner
      std::vector<PetscInt> rows(6);
      for (int d = 0; d < 3; ++d)
        rows[d] = PetscInt(a * g + 3 + d), rows[3 + d] = PetscInt(n * g + 3 + d);
      Eigen::Matrix<double, 6, 1> p;
      p << c.normal, -c.normal;
      const Eigen::Matrix<double, 6, 6, Eigen::RowMajor> pp = kbar * p * p.transpose();
      GRANPACK_PETSC(MatSetValues(b->uu, 6, rows.data(), 6, rows.data(), pp.data(), ADD_VALUES));
    }
    GRANPACK_PETSC(MatAssemblyBegin(b->uu, MAT_FINAL_ASSEMBLY));
    GRANPACK_PETSC(MatAssemblyEnd(b->uu, MAT_FINAL_ASSEMBLY));
  }

  // Pin the first grain (in the numbering) that is not divalent.
  std::int64_t pinned = 0;
  while (divalent_index.count(pinned))
    ++pinned;
  GRANPACK_CHECK(pinned < num.grains, "stiffness: the backbone is empty");
  km.pinned_grain = num.ids[pinned];
  const bool owner = pinned >= num.first && pinned < num.first + num.local;
  for (BorderedMatrix<dim>* b : matrices)
    pin(*b, pinned, g, owner, kbar);
  return km;
}

namespace {

/// Krylov-Schur on the inverse of the factorised `a` (shift-and-invert at 0 with the
/// factors): the `count` eigenpairs of `a` nearest 0, eigenvalues ascending, and with
/// `vectors` the eigenvectors (laid out like a's rows).
std::vector<double> eigenpairs_near_zero(Mat a, const DirectSolver& solver, int count,
                                         std::vector<OwnedVec>* vectors) {
  MPI_Comm comm = MPI_COMM_NULL;
  GRANPACK_PETSC(PetscObjectGetComm(reinterpret_cast<PetscObject>(a), &comm));
  PetscInt m = 0, n = 0, big_m = 0, big_n = 0;
  GRANPACK_PETSC(MatGetLocalSize(a, &m, &n));
  GRANPACK_PETSC(MatGetSize(a, &big_m, &big_n));
  count = std::min<int>(count, int(big_m));
  ShellContext ctx{&solver};
  OwnedMat inverse;
  GRANPACK_PETSC(MatCreateShell(comm, m, n, big_m, big_n, &ctx, inverse.address()));
  GRANPACK_PETSC(
      MatShellSetOperation(inverse, MATOP_MULT, reinterpret_cast<void (*)(void)>(apply_inverse)));
  EPS eps = nullptr;
  GRANPACK_PETSC(EPSCreate(comm, &eps));
  std::vector<std::pair<double, PetscInt>> found;
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
      found.emplace_back(1.0 / mu, k);
    }
    std::sort(found.begin(), found.end());
    if (vectors)
      for (const auto& [lambda, k] : found) {
        OwnedVec x;
        GRANPACK_PETSC(MatCreateVecs(a, x.address(), nullptr));
        GRANPACK_PETSC(EPSGetEigenvector(eps, k, x, nullptr));
        vectors->push_back(std::move(x));
      }
  } catch (...) {
    EPSDestroy(&eps);
    throw;
  }
  EPSDestroy(&eps);
  std::vector<double> out;
  for (const auto& [lambda, k] : found)
    out.push_back(lambda);
  return out;
}

} // namespace

std::vector<double> smallest_eigenvalues(Mat a, const DirectSolver& solver, int count, double scale,
                                         double* seconds) {
  const auto start = std::chrono::steady_clock::now();
  std::vector<double> out = eigenpairs_near_zero(a, solver, count, nullptr);
  for (double& x : out)
    x /= scale;
  if (seconds)
    *seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

SoftModes softest_modes(Mat a, const DirectSolver& solver, const GrainNumbering& numbering,
                        int grain_dofs, int count, double scale) {
  MPI_Comm comm = MPI_COMM_NULL;
  GRANPACK_PETSC(PetscObjectGetComm(reinterpret_cast<PetscObject>(a), &comm));
  std::vector<OwnedVec> vectors;
  SoftModes out;
  out.eigenvalues = eigenpairs_near_zero(a, solver, count, &vectors);
  for (double& x : out.eigenvalues)
    x /= scale;
  const std::size_t g = std::size_t(grain_dofs);
  for (const auto& v : vectors) {
    // This rank's rows are the grains numbering.first + i: each sent with its index.
    const PetscScalar* x = nullptr;
    GRANPACK_PETSC(VecGetArrayRead(v, &x));
    std::vector<double> local;
    local.reserve(std::size_t(numbering.local) * (g + 1));
    for (std::int64_t i = 0; i < numbering.local; ++i) {
      local.push_back(double(numbering.first + i));
      local.insert(local.end(), x + i * grain_dofs, x + (i + 1) * grain_dofs);
    }
    GRANPACK_PETSC(VecRestoreArrayRead(v, &x));
    const std::vector<double> all = gather_values(local, comm, 0);
    std::vector<double> mode(all.empty() ? 0 : std::size_t(numbering.grains) * g, 0.0);
    for (std::size_t k = 0; k + g < all.size(); k += g + 1)
      std::copy(all.begin() + long(k + 1), all.begin() + long(k + 1 + g),
                mode.begin() + long(std::size_t(all[k]) * g));
    out.values.push_back(std::move(mode));
  }
  if (out.values.size() && out.values.front().empty())
    out.values.clear(); // not rank 0
  return out;
}

std::vector<std::vector<GlobalId>> floppy_modes(Mat a, const GrainNumbering& numbering,
                                                int grain_dofs, double mean_kn, int count,
                                                double shift, double tolerance) {
  MPI_Comm comm = MPI_COMM_NULL;
  GRANPACK_PETSC(PetscObjectGetComm(reinterpret_cast<PetscObject>(a), &comm));
  OwnedMat shifted;
  GRANPACK_PETSC(MatDuplicate(a, MAT_COPY_VALUES, shifted.address()));
  GRANPACK_PETSC(MatShift(shifted, shift * mean_kn));
  const DirectSolver solver = factorize(shifted, true, 0.0);
  // Ask for more eigenpairs until one lies above the tolerance: the null space is complete.
  PetscInt size_a = 0;
  GRANPACK_PETSC(MatGetSize(shifted, &size_a, nullptr));
  std::vector<OwnedVec> vectors;
  std::vector<double> lambda;
  for (;;) {
    vectors.clear();
    lambda = eigenpairs_near_zero(shifted, solver, count, &vectors);
    const bool all_null = !lambda.empty() && std::size_t(count) == lambda.size() &&
                          lambda.back() / mean_kn - shift <= tolerance;
    if (!all_null || count >= size_a)
      break;
    count = int(std::min<PetscInt>(2 * PetscInt(count), size_a));
  }
  std::vector<std::vector<GlobalId>> modes;
  for (std::size_t k = 0; k < lambda.size(); ++k) {
    if (lambda[k] / mean_kn - shift > tolerance)
      continue;
    // Per-grain amplitude of this rank's rows, then every rank's (index, amplitude) pairs.
    const PetscScalar* x = nullptr;
    GRANPACK_PETSC(VecGetArrayRead(vectors[k], &x));
    std::vector<double> local(2 * numbering.local);
    for (std::int64_t i = 0; i < numbering.local; ++i) {
      double a2 = 0;
      for (int d = 0; d < grain_dofs; ++d)
        a2 += x[i * grain_dofs + d] * x[i * grain_dofs + d];
      local[2 * i] = double(numbering.first + i), local[2 * i + 1] = std::sqrt(a2);
    }
    GRANPACK_PETSC(VecRestoreArrayRead(vectors[k], &x));
    const std::vector<double> all = allgather_concat(comm, local);
    std::vector<std::pair<double, GlobalId>> amp;
    double largest = 0;
    for (std::size_t i = 0; i + 1 < all.size(); i += 2)
      largest = std::max(largest, all[i + 1]);
    for (std::size_t i = 0; i + 1 < all.size(); i += 2)
      if (all[i + 1] >= 0.1 * largest)
        amp.emplace_back(-all[i + 1], numbering.ids[std::size_t(all[i])]);
    std::sort(amp.begin(), amp.end());
    std::vector<GlobalId> grains;
    for (std::size_t i = 0; i < std::min<std::size_t>(amp.size(), 50); ++i)
      grains.push_back(amp[i].second);
    modes.push_back(std::move(grains));
  }
  return modes;
}

template KnownMechanisms remove_known_mechanisms<2>(StiffnessSystem<2>&);
template KnownMechanisms remove_known_mechanisms<3>(StiffnessSystem<3>&);

} // namespace granpack
