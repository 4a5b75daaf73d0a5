#pragma once
// The stress-controlled cell of a stage (compress, stiffen): prescribed stresses, fixed
// axes, generalised mass and strain-rate caps from the stage's controls ([AR] sec. II B,
// [GRC] eq. 3).
#include "granpack/dynamics/cell_control.h"
#include "granpack/engine/run_context.h"
#include "granpack/io/deck.h"

namespace granpack {

/// Mass of a homogeneous grain of the sample's diameter a (per unit thickness in 2D).
template <int dim> double reference_grain_mass(const RunContext<dim>& ctx);

/// The cell control for `c` on the current sample: M = cell_mass x total grain mass (x a/L0
/// with cell_mass_per_length), the targets and fixed axes, and the strain-rate cap, the
/// smaller of strain_rate_max and inertia_max / sqrt(m / (a^(dim-2) P)) (eq. 23; the inertia
/// cap needs P > 0). Collective (the total mass is a sum over ranks).
template <int dim> CellControl<dim> cell_control_of(RunContext<dim>& ctx, const CompressStage& c);

} // namespace granpack
