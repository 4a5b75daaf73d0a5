#pragma once
// Contact-network metrics of the current state for report.json: the rattler fraction x0 by
// the iterative rule of [AR] sec. III B, z = 2 N_c / n and z* = z / (1 - x0), N_c counting
// force-carrying contacts (N^e above a threshold) between non-rattlers. Collective.
#include <optional>

#include "granpack/prep/md_engine.h"

namespace granpack {

struct StateMetrics {
  double z = 0, z_star = 0, x0 = 0;
  std::int64_t backbone_contacts = 0, rattlers = 0, n = 0;
};

/// min_contacts: dim + 1 without friction, 2 with friction.
template <int dim>
StateMetrics state_metrics(RunContext<dim>& ctx, const MdEngine<dim>& engine, double threshold,
                           int min_contacts);

}  // namespace granpack
