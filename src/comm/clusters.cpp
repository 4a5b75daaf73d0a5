#include "granpack/comm/clusters.h"

#include <unordered_map>

#include "granpack/comm/gather.h"
#include "granpack/core/error.h"

namespace granpack {

namespace {
/// Union-find with path halving over the ids met so far.
struct DisjointSets {
  std::vector<std::size_t> parent;
  std::unordered_map<std::int64_t, std::size_t> index;
  std::size_t of(std::int64_t id) {
    const auto [it, added] = index.try_emplace(id, parent.size());
    if (added) parent.push_back(it->second);
    return it->second;
  }
  std::size_t find(std::size_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  /// True when a and b were in different sets.
  bool unite(std::int64_t id_a, std::int64_t id_b) {
    std::size_t a = find(of(id_a)), b = find(of(id_b));
    if (a == b) return false;
    parent[std::max(a, b)] = std::min(a, b);
    return true;
  }
};
}  // namespace

std::int64_t count_clusters(const std::vector<std::pair<GlobalId, GlobalId>>& pairs,
                            std::int64_t n_grains, MPI_Comm comm) {
  std::vector<double> mine;  // ids are < 2^53: exact as doubles
  mine.reserve(2 * pairs.size());
  for (const auto& [a, b] : pairs) {
    mine.push_back(double(a));
    mine.push_back(double(b));
  }
  const std::vector<double> all = gather_values(mine, comm, 0);
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  std::int64_t clusters = 0;
  if (rank == 0) {
    // Each successful union merges two clusters; grains in no pair stay single.
    DisjointSets sets;
    clusters = n_grains;
    for (std::size_t k = 0; k + 1 < all.size(); k += 2)
      if (sets.unite(static_cast<std::int64_t>(all[k]), static_cast<std::int64_t>(all[k + 1])))
        --clusters;
    GRANPACK_CHECK(static_cast<std::int64_t>(sets.parent.size()) <= n_grains,
                   "count_clusters: more distinct ids in the pairs than grains");
  }
  MPI_Bcast(&clusters, 1, MPI_INT64_T, 0, comm);
  return clusters;
}

}  // namespace granpack
