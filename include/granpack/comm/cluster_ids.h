#pragma once
// Each grain's cluster in the interaction network (contacts and cohesive distant pairs, as
// comm/clusters counts them for [GRC]'s aggregation): the smallest id among the grains it is
// connected to, whatever the rank count. Written per grain into /network (cluster_id).
//
// Each rank joins its pairs locally (analysis/disjoint_sets); a grain met as a ghost links the
// rank's local cluster to the one its owner found, and only these links (about one per ghost
// in a cluster, not one per contact) go to rank 0, which joins them and sends back the final
// name of every local cluster it met. Collective on d.comm().
#include <vector>

#include "granpack/analysis/coordination.h"
#include "granpack/comm/halo.h"

namespace granpack {

/// Per owned grain of `p` (owned, then the ghosts of `halo`): its cluster id, as a double
/// (ids < 2^53). `pairs`: this rank's interacting pairs by local row, ghosts included; a grain
/// in no pair is a cluster of its own (its own id).
template <int dim>
std::vector<double> cluster_ids(const ParticleStore<dim>& p, const Halo<dim>& halo,
                                const Decomposition<dim>& d,
                                const std::vector<CarryingContact>& pairs);

extern template std::vector<double> cluster_ids<2>(const ParticleStore<2>&, const Halo<2>&,
                                                   const Decomposition<2>&,
                                                   const std::vector<CarryingContact>&);
extern template std::vector<double> cluster_ids<3>(const ParticleStore<3>&, const Halo<3>&,
                                                   const Decomposition<3>&,
                                                   const std::vector<CarryingContact>&);

} // namespace granpack
