#pragma once
// Equilibrium by virtual work ([AR] eq. 15-16): the loads the contact forces balance,
// ᵀG f, against F_ext = (0 on every grain, Omega Sigma_alpha on the strains; scaled by
// 1/L_alpha like the strain unknowns). Collective. relative_to_forces: residuals over |f|,
// the contact forces, instead of |F_ext| (with cohesion, where F_ext may vanish: P* = 0).
#include "granpack/rigidity/stiffness_system.h"

namespace granpack {

struct VirtualWork {
  double residual = 0;        ///< |ᵀG f - F_ext| / |F_ext| (or / |f|)
  double grain_residual = 0;  ///< the grain rows' part of it: |ᵀG f|_grains / |F_ext| (or / |f|)
  double max_grain_force = 0; ///< largest |net force| component on a grain (N), torques / ell
  Vec<3> stress_from_forces = Vec<3>::Zero(); ///< sum F_a r_a / Omega, eq. (16) (first dim entries)
};

template <int dim>
VirtualWork check_virtual_work(const StiffnessSystem<dim>& s, const Vec<dim>& prescribed_stress,
                               double volume, bool relative_to_forces = false);

} // namespace granpack
