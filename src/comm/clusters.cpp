#include "granpack/comm/clusters.h"

#include <algorithm>
#include <unordered_map>

#include "granpack/analysis/disjoint_sets.h"
#include "granpack/comm/gather.h"
#include "granpack/core/error.h"

namespace granpack {

namespace {
/// Every rank's pairs on rank 0, two ids after another (empty elsewhere).
std::vector<double> gather_pairs(const std::vector<std::pair<GlobalId, GlobalId>>& pairs,
                                 MPI_Comm comm) {
  std::vector<double> mine; // ids are < 2^53: exact as doubles
  mine.reserve(2 * pairs.size());
  for (const auto& [a, b] : pairs) {
    mine.push_back(double(a));
    mine.push_back(double(b));
  }
  return gather_values(mine, comm, 0);
}
} // namespace

std::int64_t count_clusters(const std::vector<std::pair<GlobalId, GlobalId>>& pairs,
                            std::int64_t n_grains, MPI_Comm comm) {
  const std::vector<double> all = gather_pairs(pairs, comm);
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

ClusterSplit split_clusters(const std::vector<std::pair<GlobalId, GlobalId>>& pairs,
                            MPI_Comm comm) {
  const std::vector<double> all = gather_pairs(pairs, comm);
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  ClusterSplit out;
  std::int64_t counts[3] = {0, 0, 0}; // size of the largest, other clusters, their grains
  if (rank == 0) {
    DisjointSets sets;
    for (std::size_t k = 0; k + 1 < all.size(); k += 2)
      sets.unite(static_cast<std::int64_t>(all[k]), static_cast<std::int64_t>(all[k + 1]));
    // Members per root, and the smallest id of each cluster (the tie-break).
    std::unordered_map<std::size_t, std::pair<std::int64_t, GlobalId>> size_and_min;
    for (const auto& [id, x] : sets.index) {
      auto [it, added] = size_and_min.try_emplace(sets.find(x), 0, id);
      ++it->second.first;
      it->second.second = std::min(it->second.second, GlobalId(id));
    }
    std::size_t best = 0;
    std::pair<std::int64_t, GlobalId> best_key{-1, 0};
    for (const auto& [root, key] : size_and_min)
      if (key.first > best_key.first ||
          (key.first == best_key.first && key.second < best_key.second))
        best = root, best_key = key;
    for (const auto& [id, x] : sets.index)
      if (sets.find(x) == best)
        out.largest.push_back(id);
    std::sort(out.largest.begin(), out.largest.end());
    counts[0] = std::int64_t(out.largest.size());
    counts[1] = std::int64_t(size_and_min.size()) - (size_and_min.empty() ? 0 : 1);
    counts[2] = std::int64_t(sets.index.size()) - counts[0];
  }
  MPI_Bcast(counts, 3, MPI_INT64_T, 0, comm);
  out.largest.resize(std::size_t(counts[0]));
  MPI_Bcast(out.largest.data(), int(counts[0]), MPI_INT64_T, 0, comm);
  out.other_clusters = counts[1];
  out.other_grains = counts[2];
  return out;
}

} // namespace granpack
