#pragma once
// Contact-network metrics of the engine's current state for report.json: x0 by the iterative
// rule of [AR] sec. III B, z = 2 N_c / n and z* = z / (1 - x0), N_c counting force-carrying
// contacts (N^e above a threshold) between non-rattlers. Collective.
#include "granpack/prep/backbone.h"
#include "granpack/prep/md_engine.h"

namespace granpack {

/// min_contacts: dim + 1 without friction, 2 with friction.
template <int dim>
StateMetrics state_metrics(RunContext<dim>& ctx, const MdEngine<dim>& engine, double threshold,
                           int min_contacts);

}  // namespace granpack
