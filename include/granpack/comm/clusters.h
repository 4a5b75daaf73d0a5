#pragma once
// Connected clusters of the interaction network (contacts and cohesive distant pairs), for
// [GRC] method 2's aggregation, which ends when all grains form a single cluster. The pairs
// are gathered on rank 0 (two ids per pair: fine for the 10^3-10^5 grains of aggregation
// runs, not meant for 10^7) and merged there by union-find; the count is broadcast.
// Collective on comm.
#include <mpi.h>

#include <cstdint>
#include <vector>

#include "granpack/core/vec.h"

namespace granpack {

/// Number of clusters among `n_grains` grains (those in no pair are clusters of their own),
/// given this rank's interacting pairs (each pair listed by one rank).
std::int64_t count_clusters(const std::vector<std::pair<GlobalId, GlobalId>>& pairs,
                            std::int64_t n_grains, MPI_Comm comm);

/// The clusters of grains met in `pairs` (grains in no pair are not counted), by the same
/// gather: the sorted ids of the largest (the smallest id among equal sizes, for a result
/// that does not depend on the rank count), and how many others there are with how many
/// grains. Every rank gets the result.
struct ClusterSplit {
  std::vector<GlobalId> largest;
  std::int64_t other_clusters = 0, other_grains = 0;
};
ClusterSplit split_clusters(const std::vector<std::pair<GlobalId, GlobalId>>& pairs, MPI_Comm comm);

} // namespace granpack
