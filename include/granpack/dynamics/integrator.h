#pragma once
// Velocity-Verlet ("kick-drift-kick") integration of the grains in scaled coordinates.
//
// Why this scheme: it is second order, time reversible for conservative forces (so the
// momentum and energy tests are meaningful), needs one force evaluation per step, and is
// the scheme of LAMMPS/LIGGGHTS, which makes side-by-side comparisons fair. Velocity-dependent
// forces (viscous damping, tangential increments) are evaluated with the half-step
// velocities, the standard DEM choice.
//
// Equations ([AR] eq. 6 with the extra Parrinello-Rahman terms omitted, as the paper does):
// the stored velocity is the fluctuating velocity v = L ds/dt, so
//   dv/dt = F/m,   ds/dt = v / L,   dL/dt = Ldot,
// and the real velocity of a grain is v + Ldot s (the affine part), which the contact
// kernels add to relative velocities as (Ldot/L) * r_ij.
#include "granpack/core/cell.h"
#include "granpack/core/particles.h"

namespace granpack {

/// v += h F/m and omega += h torque/I for the owned grains (h = dt/2 in velocity Verlet).
template <int dim> void kick(ParticleStore<dim>& p, double h);

/// s += dt v/L for the owned grains (positions may leave [0,1): migration wraps them), and
/// the orientations advance with omega (quaternion in 3D, angle in 2D).
template <int dim> void drift(ParticleStore<dim>& p, const Cell<dim>& cell, double dt);

/// Total momentum sum m v of the owned grains (fluctuating velocities).
template <int dim> Vec<dim> momentum(const ParticleStore<dim>& p);

/// Kinetic energy of the owned grains, translational (fluctuating) plus rotational.
template <int dim> double kinetic_energy(const ParticleStore<dim>& p);

} // namespace granpack
