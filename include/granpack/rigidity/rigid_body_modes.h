#pragma once
// The rigid-body motions of the backbone as grain-block vectors: the near-null space that an
// algebraic multigrid needs to coarsen the stiffness matrix well (PCGAMG builds its coarse
// spaces by restricting these vectors to aggregates of grains). A rigid translation t
// (u_i = t, rho_i = 0) and a rigid rotation omega (u_i = omega x x_i, rho_i = ell omega, the
// contact points moving together) leave every contact's relative displacement zero, so that
// locally, on an aggregate, they are null vectors of K(1). Globally the periodic cell breaks
// the rotations (x jumps across the boundary), which is why they are only a near-null space
// and are not projected out of the solves. Collective.
#include "granpack/rigidity/stiffness_system.h"

namespace granpack {

/// dim translations and rot_dim<dim> rotations about the cell centre, orthonormalised, laid
/// out like K_uu's rows (block size g: u then rho with friction, u alone without).
template <int dim>
OwnedNullSpace rigid_body_modes(const PackingView<dim>& v, const StiffnessSystem<dim>& s);

} // namespace granpack
