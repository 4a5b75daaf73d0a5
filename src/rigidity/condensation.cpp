#include "granpack/rigidity/condensation.h"

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
    for (int a = 0; a < nv; ++a) {
      PetscScalar dot = 0;
      GRANPACK_PETSC(VecDot(x, b.eu[a], &dot)); // VecDot(x, y) = yᴴ x
      m.schur(a, beta) -= dot;
    }
  }
  m.tensor = physical<dim>(m.schur, layout, volume, stress);
  m.affine = physical<dim>(b.ee, layout, volume, stress);
  m.stiffness = m.tensor.template topLeftCorner<dim, dim>();
  m.bulk = m.stiffness.sum() / (dim * dim);
  const double diag = m.stiffness.trace() / dim;
  const double off = (m.stiffness.sum() - m.stiffness.trace()) / (dim * (dim - 1));
  m.shear_diag = 0.5 * (diag - off);
  m.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return m;
}

template Moduli<2> condense<2>(const BorderedMatrix<2>&, const GrainSolve&,
                               const RigidityLayout<2>&, double, const VoigtVec<2>&);
template Moduli<3> condense<3>(const BorderedMatrix<3>&, const GrainSolve&,
                               const RigidityLayout<3>&, double, const VoigtVec<3>&);

} // namespace granpack
