#pragma once
// Contact-network metrics of the engine's current state for report.json: x0 by the iterative
// rule of [AR] sec. III B, z = 2 N_c / n and z* = z / (1 - x0), N_c counting force-carrying
// contacts (N^e above a threshold) between non-rattlers. Collective.
#include "granpack/comm/backbone.h"
#include "granpack/engine/md_engine.h"

namespace granpack {

/// min_contacts: min_backbone_contacts(dim, μ) of contact/derived_constants.h.
template <int dim>
StateMetrics state_metrics(RunContext<dim>& ctx, const MdEngine<dim>& engine, double threshold,
                           int min_contacts);

/// [GRC] sec. III A coordination of a cohesive packing: every interaction counts (contacts
/// and distant attractions), split by the sign of the static normal force N = N^e + N^a into
/// repulsive (N > threshold), attractive (N < -threshold) and unstressed (|N| <= threshold:
/// contacts at the isolated deflection h0 carry N^e = F0, N = 0). z = 2 N_int / n.
struct CohesiveCoordination {
  double z = 0, z_plus = 0, z_minus = 0, z_zero = 0;
  double distant_fraction = 0; ///< distant pairs / all interactions
};

/// Collective.
template <int dim>
CohesiveCoordination cohesive_coordination(RunContext<dim>& ctx, const MdEngine<dim>& engine,
                                           double threshold);

} // namespace granpack
