#include "granpack/rigidity/condensation.h"

#include <chrono>

namespace granpack {

template <int dim>
Moduli<dim> condense(const BorderedMatrix<dim>& b, const GrainSolve& solve, const Vec<dim>& cell,
                     double volume, const Vec<dim>& stress) {
  const auto start = std::chrono::steady_clock::now();
  Moduli<dim> m;
  OwnedVec x;
  GRANPACK_PETSC(VecDuplicate(b.ue[0], x.address()));
  m.schur = b.ee;
  for (int beta = 0; beta < dim; ++beta) {
    solve(b.ue[beta], x);
    for (int a = 0; a < dim; ++a) {
      PetscScalar dot = 0;
      GRANPACK_PETSC(VecDot(x, b.eu[a], &dot)); // VecDot(x, y) = yᴴ x
      m.schur(a, beta) -= dot;
    }
  }
  const Tensor<dim> kc = cell.asDiagonal() * m.schur * cell.asDiagonal();
  m.stiffness = kc / volume;
  for (int a = 0; a < dim; ++a)
    m.stiffness.row(a).array() += stress[a];
  m.bulk = m.stiffness.sum() / (dim * dim);
  const double diag = m.stiffness.trace() / dim;
  const double off = (m.stiffness.sum() - m.stiffness.trace()) / (dim * (dim - 1));
  m.shear_diag = 0.5 * (diag - off);
  m.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return m;
}

template Moduli<2> condense<2>(const BorderedMatrix<2>&, const GrainSolve&, const Vec<2>&, double,
                               const Vec<2>&);
template Moduli<3> condense<3>(const BorderedMatrix<3>&, const GrainSolve&, const Vec<3>&, double,
                               const Vec<3>&);

} // namespace granpack
