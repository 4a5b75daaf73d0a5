#include "granpack/rigidity/condensation.h"

#include <array>
#include <chrono>

namespace granpack {

namespace {

/// c_IJ from a scaled strain block: S m S / Omega, plus sigma_I in the diagonal columns (the
/// volume change -tr(eps) Omega at fixed Cauchy stress; shear strains keep the volume).
template <int dim>
VoigtMatrix<dim> physical(const VoigtMatrix<dim>& m, const RigidityLayout<dim>& l, double volume,
                          const VoigtVec<dim>& stress) {
  VoigtVec<dim> s;
  for (int i = 0; i < voigt_size<dim>; ++i)
    s[i] = l.strain_scale(i);
  VoigtMatrix<dim> c = s.asDiagonal() * m * s.asDiagonal() / volume;
  for (int j = 0; j < dim; ++j)
    c.col(j) += stress;
  return c;
}

/// The tensor, its affine part and the moduli from m.schur (filled in), and the time since
/// `start`.
template <int dim>
void finish(Moduli<dim>& m, const BorderedMatrix<dim>& b, const RigidityLayout<dim>& layout,
            double volume, const VoigtVec<dim>& stress,
            std::chrono::steady_clock::time_point start) {
  m.tensor = physical<dim>(m.schur, layout, volume, stress);
  m.affine = physical<dim>(b.ee, layout, volume, stress);
  m.stiffness = m.tensor.template topLeftCorner<dim, dim>();
  m.bulk = m.stiffness.sum() / (dim * dim);
  const double diag = m.stiffness.trace() / dim;
  const double off = (m.stiffness.sum() - m.stiffness.trace()) / (dim * (dim - 1));
  m.shear_diag = 0.5 * (diag - off);
  m.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

PetscScalar dot(::Vec x, ::Vec y) {
  PetscScalar d = 0;
  GRANPACK_PETSC(VecDot(x, y, &d)); // VecDot(x, y) = yᴴ x
  return d;
}

} // namespace

template <int dim>
Moduli<dim> condense(const BorderedMatrix<dim>& b, const GrainSolve& solve,
                     const RigidityLayout<dim>& layout, double volume,
                     const VoigtVec<dim>& stress) {
  constexpr int nv = voigt_size<dim>;
  const auto start = std::chrono::steady_clock::now();
  Moduli<dim> m;
  OwnedVec x;
  GRANPACK_PETSC(VecDuplicate(b.ue[0], x.address()));
  m.schur = b.ee;
  for (int beta = 0; beta < nv; ++beta) {
    solve(b.ue[beta], x);
    for (int a = 0; a < nv; ++a)
      m.schur(a, beta) -= dot(x, b.eu[a]);
  }
  finish(m, b, layout, volume, stress, start);
  return m;
}

template <int dim>
Moduli<dim> condense_approximately(const BorderedMatrix<dim>& b, const GrainSolve& solve,
                                   const GrainSolve& adjoint, const RigidityLayout<dim>& layout,
                                   double volume, const VoigtVec<dim>& stress) {
  constexpr int nv = voigt_size<dim>;
  const auto start = std::chrono::steady_clock::now();
  Moduli<dim> m;
  std::array<OwnedVec, nv> x, y, r; // solutions, adjoint solutions, residuals b - K x
  for (int a = 0; a < nv; ++a) {
    GRANPACK_PETSC(VecDuplicate(b.ue[0], x[a].address()));
    GRANPACK_PETSC(VecDuplicate(b.ue[0], r[a].address()));
    solve(b.ue[a], x[a]);
    GRANPACK_PETSC(MatMult(b.uu, x[a], r[a]));
    GRANPACK_PETSC(VecAYPX(r[a], -1.0, b.ue[a]));
  }
  for (int a = 0; adjoint && a < nv; ++a) { // after the forward solves: the solver's log order
    GRANPACK_PETSC(VecDuplicate(b.ue[0], y[a].address()));
    adjoint(b.eu[a], y[a]);
  }
  // S_ab = K_ee - (eu_a . x_b + y_a . r_b): exact if either solve is, and off by
  // -(y_a - y*_a)ᵀ K (x_b - x*_b) otherwise, second order in the two errors.
  m.schur = b.ee;
  for (int a = 0; a < nv; ++a)
    for (int beta = 0; beta < nv; ++beta)
      m.schur(a, beta) -= dot(x[beta], b.eu[a]) + dot(r[beta], adjoint ? y[a] : x[a]);
  finish(m, b, layout, volume, stress, start);
  return m;
}

template Moduli<2> condense<2>(const BorderedMatrix<2>&, const GrainSolve&,
                               const RigidityLayout<2>&, double, const VoigtVec<2>&);
template Moduli<3> condense<3>(const BorderedMatrix<3>&, const GrainSolve&,
                               const RigidityLayout<3>&, double, const VoigtVec<3>&);
template Moduli<2> condense_approximately<2>(const BorderedMatrix<2>&, const GrainSolve&,
                                             const GrainSolve&, const RigidityLayout<2>&, double,
                                             const VoigtVec<2>&);
template Moduli<3> condense_approximately<3>(const BorderedMatrix<3>&, const GrainSolve&,
                                             const GrainSolve&, const RigidityLayout<3>&, double,
                                             const VoigtVec<3>&);

} // namespace granpack
