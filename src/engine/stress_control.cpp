#include "granpack/engine/stress_control.h"

#include <mpi.h>

#include <algorithm>
#include <cmath>

#include "granpack/comm/reduce.h"
#include "granpack/core/particles.h"

namespace granpack {

template <int dim> double reference_grain_mass(const RunContext<dim>& ctx) {
  return HomogeneousGrain<dim>::mass(ctx.deck->material.density, ctx.deck->sample.diameter);
}

template <int dim> CellControl<dim> cell_control_of(RunContext<dim>& ctx, const CompressStage& c) {
  const double a = ctx.deck->sample.diameter;
  CellControl<dim> cell;
  double total_mass = 0;
  for (std::size_t i = 0; i < ctx.system.particles.n_owned(); ++i)
    total_mass += ctx.system.particles.mass[i];
  total_mass = global_sum(ctx.world, total_mass);
  cell.mass = c.cell_mass * total_mass;
  // [GRC] eq. 3 drives the strain eps = -L/L0 with M = 0.3 sum m / L (L in units of a); in
  // the form M' d2L/dt2 = (Omega/L_a)(sigma - Sigma) used here this is M' = M a / L0 for a
  // square cell.
  if (c.cell_mass_per_length)
    cell.mass *= a / (ctx.system.cell.length.sum() / dim);
  for (int k = 0; k < dim; ++k) {
    cell.target[k] = c.stress[k];
    cell.fixed[k] = c.fixed[k];
  }
  if (c.strain_rate_max)
    cell.max_strain_rate = *c.strain_rate_max;
  // Inertia number I = eps_dot sqrt(m / (a P)) (eq. 23), m the mass of a grain of diameter a
  // (in 2D, per unit thickness: I = eps_dot sqrt(m / P)).
  if (c.inertia_max && c.pressure > 0) {
    const double inertia_time =
        std::sqrt(reference_grain_mass(ctx) / ((dim == 3 ? a : 1.0) * c.pressure));
    cell.max_strain_rate = std::min(cell.max_strain_rate, *c.inertia_max / inertia_time);
  }
  return cell;
}

template double reference_grain_mass<2>(const RunContext<2>&);
template double reference_grain_mass<3>(const RunContext<3>&);
template CellControl<2> cell_control_of<2>(RunContext<2>&, const CompressStage&);
template CellControl<3> cell_control_of<3>(RunContext<3>&, const CompressStage&);

} // namespace granpack
