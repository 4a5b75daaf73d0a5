#include "granpack/rigidity/virtual_work.h"

#include <cmath>

#include "granpack/comm/reduce.h"

namespace granpack {

template <int dim>
VirtualWork check_virtual_work(const StiffnessSystem<dim>& s, const Vec<dim>& prescribed_stress,
                               double volume, bool relative_to_forces) {
  OwnedVec loads, ext;
  GRANPACK_PETSC(MatCreateVecs(s.G, loads.address(), nullptr));
  GRANPACK_PETSC(MatMultTranspose(s.G, s.f, loads));
  GRANPACK_PETSC(VecDuplicate(loads, ext.address()));
  GRANPACK_PETSC(VecSet(ext, 0.0));
  const PetscInt strain_col = PetscInt(s.numbering.grains * s.grain_dofs());
  PetscInt first = 0, last = 0;
  GRANPACK_PETSC(VecGetOwnershipRange(ext, &first, &last));
  VirtualWork w;
  for (int a = 0; a < dim; ++a) {
    const PetscInt i = strain_col + a;
    if (i >= first && i < last) {
      const PetscScalar value = volume * prescribed_stress[a] / s.layout.cell[a];
      GRANPACK_PETSC(VecSetValue(ext, i, value, INSERT_VALUES));
    }
  }
  GRANPACK_PETSC(VecAssemblyBegin(ext));
  GRANPACK_PETSC(VecAssemblyEnd(ext));

  // Stress the forces carry (eq. 16), read from the strain entries of ᵀG f.
  std::vector<double> strain(dim, 0.0);
  {
    const PetscScalar* x = nullptr;
    GRANPACK_PETSC(VecGetArrayRead(loads, &x));
    double local_max = 0;
    for (PetscInt i = first; i < last; ++i) {
      if (i >= strain_col)
        strain[i - strain_col] = x[i - first];
      else
        local_max = std::max(local_max, std::abs(x[i - first]));
    }
    GRANPACK_PETSC(VecRestoreArrayRead(loads, &x));
    w.max_grain_force = global_max(s.comm, local_max);
    global_sum_in_place(s.comm, strain);
  }
  for (int a = 0; a < dim; ++a)
    w.stress_from_forces[a] = strain[a] * s.layout.cell[a] / volume;

  PetscReal ext_norm = 0, diff_norm = 0, strain_diff2 = 0;
  GRANPACK_PETSC(VecNorm(ext, NORM_2, &ext_norm));
  GRANPACK_PETSC(VecAXPY(loads, -1.0, ext));
  GRANPACK_PETSC(VecNorm(loads, NORM_2, &diff_norm));
  for (int a = 0; a < dim; ++a) {
    const double d = strain[a] - volume * prescribed_stress[a] / s.layout.cell[a];
    strain_diff2 += d * d;
  }
  PetscReal reference = ext_norm;
  if (relative_to_forces)
    GRANPACK_PETSC(VecNorm(s.f, NORM_2, &reference));
  w.residual = diff_norm / reference;
  w.grain_residual = std::sqrt(std::max(0.0, diff_norm * diff_norm - strain_diff2)) / reference;
  return w;
}

template VirtualWork check_virtual_work<2>(const StiffnessSystem<2>&, const Vec<2>&, double, bool);
template VirtualWork check_virtual_work<3>(const StiffnessSystem<3>&, const Vec<3>&, double, bool);

} // namespace granpack
