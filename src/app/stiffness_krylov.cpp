#include "granpack/app/stiffness_krylov.h"

#ifdef GRANPACK_HAVE_RIGIDITY

#include <algorithm>
#include <cmath>

#include "granpack/rigidity/iterative_solver.h"
#include "granpack/rigidity/rigid_body_modes.h"

namespace granpack {

namespace {

nlohmann::json solver_json(const IterativeSolver& s) {
  return {{"method", s.method},
          {"preconditioner", s.preconditioner},
          {"iterations", s.iterations},
          {"residuals", s.residuals},
          {"setup_seconds", s.setup_seconds},
          {"solve_seconds", s.solve_seconds},
          {"converged", s.converged},
          {"failure", s.converged ? nlohmann::json() : nlohmann::json(s.failure)}};
}

/// max_I |K_eu,I - K_ue,I| / |K_ue,I|: how far the border rows are from the columns.
template <int dim> double border_asymmetry(const BorderedMatrix<dim>& b) {
  double worst = 0;
  for (int a = 0; a < voigt_size<dim>; ++a) {
    OwnedVec d;
    GRANPACK_PETSC(VecDuplicate(b.ue[a], d.address()));
    GRANPACK_PETSC(VecWAXPY(d, -1.0, b.eu[a], b.ue[a]));
    PetscReal diff = 0, norm = 0;
    GRANPACK_PETSC(VecNorm(d, NORM_2, &diff));
    GRANPACK_PETSC(VecNorm(b.ue[a], NORM_2, &norm));
    worst = std::max(worst, norm > 0 ? diff / norm : diff);
  }
  return worst;
}

/// For a symmetric grain block, whether the forward solutions x_I can stand for the adjoint
/// ones y_I = K_uu^{-1} K_eu,I: y_I - x_I is the solve's error plus K_uu^{-1}(K_eu,I - K_ue,I),
/// so the condensation's error gains a term of order (asymmetry) x rtol x cond(K_uu). K(1)'s
/// border is symmetric by construction (2e-16 measured); that of K(1) + K(2) without friction
/// to 1e-9 on A (measured; its strain rows and columns come from different terms): below 1e-8
/// the six adjoint solves are skipped.
template <int dim> bool symmetric_border(const BorderedMatrix<dim>& b) {
  return border_asymmetry(b) <= 1e-8;
}

GrainSolve forward(IterativeSolver& s) {
  return [&s](::Vec b, ::Vec x) { s.solve(b, x); };
}
GrainSolve adjoint(IterativeSolver& s) {
  return [&s](::Vec b, ::Vec x) { s.solve_transpose(b, x); };
}

} // namespace

template <int dim>
KrylovModuli<dim> krylov_moduli(const PackingView<dim>& v, const StiffnessSystem<dim>& s,
                                const VoigtVec<dim>& stress, double rtol, int max_iterations) {
  KrylovModuli<dim> out;
  const double volume = v.system.cell.volume();
  const OwnedNullSpace modes = rigid_body_modes(v, s);
  // The multigrid is built on a symmetric positive-definite matrix whose null space is G's:
  // K(1), or ᵀG|𝒦|G with distant pairs (whose -F0/D0 makes K(1) indefinite: GMRES then).
  const bool k1_spd = !s.has_gram();
  const BorderedMatrix<dim>& mech = s.has_gram() ? s.gram : s.k1;
  // K(1)'s grain block is symmetric: its adjoint solves are forward ones, needed only if the
  // border is not (it is, by construction; checked). K = K(1) + K(2) is solved with K(1)'s
  // multigrid, positive definite by construction. Without friction (central forces) K's grain
  // block is symmetric but K(2) < 0 may make it indefinite: MINRES, and forward solves with the
  // border rows as right-hand sides if they are not the columns. (CG with a multigrid built on K
  // itself broke down on A replicated 2x2x2, |r|/|b| = 3e-3 after 515 iterations, and GMRES
  // with that multigrid had not finished one solve in 25 min: docs/stiffness.md.) With
  // friction (or distant pairs) K is not symmetric: GMRES (K(2) is a perturbation of relative
  // size h/a), and transposed solves for the adjoint.
  const bool k_uu_symmetric = !s.layout.rotations && !s.has_gram();
  IterativeSolver k1 =
      iterative_solver(s.k1.uu, mech.uu, modes, k1_spd ? KrylovMethod::kCg : KrylovMethod::kGmres,
                       rtol, max_iterations);
  k1.label = "K(1)";
  out.k1 = condense_approximately<dim>(s.k1, forward(k1),
                                       symmetric_border(s.k1) ? GrainSolve() : forward(k1),
                                       s.layout, volume, VoigtVec<dim>::Zero());
  out.report["K1"] = solver_json(k1);
  out.converged = out.converged && k1.converged;
  if (!k_uu_symmetric) {
    IterativeSolver k =
        iterative_solver_sharing(s.k.uu, k1, KrylovMethod::kGmres, rtol, max_iterations);
    k.label = "K(1)+K(2)";
    out.k = condense_approximately<dim>(s.k, forward(k), adjoint(k), s.layout, volume, stress);
    out.report["K"] = solver_json(k);
    out.converged = out.converged && k.converged;
  } else {
    const bool border = symmetric_border(s.k);
    IterativeSolver k =
        iterative_solver_sharing(s.k.uu, k1, KrylovMethod::kMinres, rtol, max_iterations);
    k.label = "K(1)+K(2)";
    out.k = condense_approximately<dim>(s.k, forward(k), border ? GrainSolve() : forward(k),
                                        s.layout, volume, stress);
    out.report["K"] = solver_json(k);
    if (!k.converged) {
      // MINRES needs only the preconditioner to be positive definite; should it still stop
      // short (a preconditioner too poor for the iteration limit), GMRES with the same one.
      IterativeSolver g =
          iterative_solver_sharing(s.k.uu, k1, KrylovMethod::kGmres, rtol, max_iterations);
      g.label = "K(1)+K(2) (GMRES after MINRES)";
      out.k = condense_approximately<dim>(s.k, forward(g), border ? GrainSolve() : forward(g),
                                          s.layout, volume, stress);
      out.report["K_minres"] = out.report["K"];
      out.report["K"] = solver_json(g);
      k.converged = g.converged;
    }
    out.converged = out.converged && k.converged;
  }
  out.report["border_asymmetry"] = {{"K1", border_asymmetry(s.k1)}, {"K", border_asymmetry(s.k)}};
  out.report["rtol"] = rtol;
  out.report["max_iterations"] = max_iterations;
  out.report["near_null_space"] = "rigid-body modes (" + std::to_string(dim + rot_dim<dim>) +
                                  ": translations, rotations about the cell centre)";
  out.report["schur_estimate"] = "second order: K_ee - (K_eu x + y (K_ue - K_uu x))";
  return out;
}

template KrylovModuli<2> krylov_moduli<2>(const PackingView<2>&, const StiffnessSystem<2>&,
                                          const VoigtVec<2>&, double, int);
template KrylovModuli<3> krylov_moduli<3>(const PackingView<3>&, const StiffnessSystem<3>&,
                                          const VoigtVec<3>&, double, int);

} // namespace granpack

#endif // GRANPACK_HAVE_RIGIDITY
