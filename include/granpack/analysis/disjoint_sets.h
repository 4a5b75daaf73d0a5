#pragma once
// Union-find over global ids, the kernel of the cluster analyses: comm/clusters (how many
// clusters, the largest) and comm/cluster_ids (each grain's cluster, in /network). MPI-free.
#include <cstddef>
#include <cstdint>
#include <span>
#include <unordered_map>
#include <utility>
#include <vector>

#include "granpack/core/vec.h"

namespace granpack {

/// Union-find with path halving over the ids met so far (roots: the first-met index).
struct DisjointSets {
  std::vector<std::size_t> parent;
  std::unordered_map<std::int64_t, std::size_t> index;
  std::size_t of(std::int64_t id);
  std::size_t find(std::size_t x);
  /// True when a and b were in different sets.
  bool unite(std::int64_t id_a, std::int64_t id_b);
};

/// Every id met in `links` -> the smallest id of its connected component: a name for a
/// cluster that depends neither on the order of the links nor on how they were split.
std::unordered_map<GlobalId, GlobalId>
smallest_member(std::span<const std::pair<GlobalId, GlobalId>> links);

} // namespace granpack
