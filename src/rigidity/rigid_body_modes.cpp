#include "granpack/rigidity/rigid_body_modes.h"

#include <array>
#include <vector>

namespace granpack {

namespace {

/// u = omega x x for the unit rotation `k` (about axis k in 3D, about z in 2D).
template <int dim> Vec<dim> rotated(const Vec<dim>& x, int k) {
  if constexpr (dim == 2) {
    (void)k;
    return Vec<2>(-x[1], x[0]);
  } else {
    return Vec<3>::Unit(k).cross(x);
  }
}

} // namespace

template <int dim>
OwnedNullSpace rigid_body_modes(const PackingView<dim>& v, const StiffnessSystem<dim>& s) {
  constexpr int modes = dim + rot_dim<dim>;
  const int g = s.grain_dofs();
  const auto& p = v.particles();
  const auto& num = s.numbering;
  std::array<OwnedVec, modes> vecs;
  for (auto& x : vecs)
    GRANPACK_PETSC(MatCreateVecs(s.k1.uu, x.address(), nullptr));
  // Centres relative to the cell centre: the rotations then have no large translation part
  // for the orthonormalisation to cancel.
  const Vec<dim> centre = 0.5 * v.system.cell.length;
  std::vector<PetscInt> rows(g);
  std::vector<PetscScalar> values(g);
  for (std::size_t i = 0; i < p.n_owned(); ++i) {
    if (v.rattler(i))
      continue;
    const auto it = num.index.find(p.id[i]);
    if (it == num.index.end())
      continue; // not in the analysed network (a detached cluster)
    for (int d = 0; d < g; ++d)
      rows[d] = PetscInt(it->second * g + d);
    const Vec<dim> x = v.system.cell.to_real(Cell<dim>::wrap(p.position[i])) - centre;
    for (int m = 0; m < modes; ++m) {
      std::fill(values.begin(), values.end(), 0.0);
      if (m < dim) {
        values[m] = 1.0;
      } else {
        const int k = m - dim;
        const Vec<dim> u = rotated<dim>(x, k);
        for (int d = 0; d < dim; ++d)
          values[d] = u[d];
        if (s.layout.rotations)
          values[dim + k] = s.layout.ell; // rho = ell theta
      }
      GRANPACK_PETSC(VecSetValues(vecs[m], g, rows.data(), values.data(), INSERT_VALUES));
    }
  }
  for (auto& x : vecs) {
    GRANPACK_PETSC(VecAssemblyBegin(x));
    GRANPACK_PETSC(VecAssemblyEnd(x));
  }
  // Modified Gram-Schmidt: MatNullSpaceCreate wants an orthonormal basis.
  for (int m = 0; m < modes; ++m) {
    for (int q = 0; q < m; ++q) {
      PetscScalar dot = 0;
      GRANPACK_PETSC(VecDot(vecs[m], vecs[q], &dot));
      GRANPACK_PETSC(VecAXPY(vecs[m], -dot, vecs[q]));
    }
    GRANPACK_PETSC(VecNormalize(vecs[m], nullptr));
  }
  std::array<::Vec, modes> raw;
  for (int m = 0; m < modes; ++m)
    raw[m] = vecs[m];
  OwnedNullSpace space;
  GRANPACK_PETSC(MatNullSpaceCreate(s.comm, PETSC_FALSE, modes, raw.data(), space.address()));
  return space;
}

template OwnedNullSpace rigid_body_modes<2>(const PackingView<2>&, const StiffnessSystem<2>&);
template OwnedNullSpace rigid_body_modes<3>(const PackingView<3>&, const StiffnessSystem<3>&);

} // namespace granpack
