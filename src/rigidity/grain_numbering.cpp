#include "granpack/rigidity/grain_numbering.h"

#include <metis.h>

#include <algorithm>
#include <numeric>

#include "granpack/comm/broadcast.h"
#include "granpack/comm/communicator.h"
#include "granpack/comm/gather.h"
#include "granpack/core/error.h"

namespace granpack {

GrainNumbering number_backbone_grains(MPI_Comm comm, const std::vector<GlobalId>& owned_grains,
                                      const std::vector<std::pair<GlobalId, GlobalId>>& edges) {
  const int size = size_of(comm), rank = rank_of(comm);
  std::vector<int> owner;
  // As bytes, as the ids travelled before comm/ gathered them (the same bits either way).
  const std::vector<GlobalId> ids = gather_on_root<Transfer::bytes>(comm, owned_grains, 0, &owner);
  const auto pairs = gather_on_root(comm, edges);

  GrainNumbering num;
  std::vector<GlobalId> ordered; // ids in global-index order
  std::vector<std::int64_t> per_part(size, 0);
  std::int64_t cuts[2] = {0, 0};
  int error = 0;
  if (rank == 0) {
    idx_t n = static_cast<idx_t>(ids.size());
    std::vector<idx_t> vertex(ids.size());
    std::iota(vertex.begin(), vertex.end(), 0);
    std::sort(vertex.begin(), vertex.end(), [&](idx_t a, idx_t b) { return ids[a] < ids[b]; });
    std::vector<GlobalId> sorted(ids.size());
    for (std::size_t k = 0; k < ids.size(); ++k)
      sorted[k] = ids[vertex[k]];
    auto vertex_of = [&](GlobalId id) {
      const auto it = std::lower_bound(sorted.begin(), sorted.end(), id);
      return it != sorted.end() && *it == id ? vertex[it - sorted.begin()] : idx_t(-1);
    };
    // CSR adjacency (METIS wants both directions).
    std::vector<idx_t> degree(n + 1, 0), a, b;
    for (const auto& [i, j] : pairs) {
      const idx_t u = vertex_of(i), w = vertex_of(j);
      if (u < 0 || w < 0)
        error = 1;
      if (u < 0 || w < 0 || u == w)
        continue;
      a.push_back(u), b.push_back(w);
      ++degree[u + 1], ++degree[w + 1];
    }
    std::vector<idx_t> xadj(n + 1, 0), adjncy(2 * a.size());
    std::partial_sum(degree.begin(), degree.end(), xadj.begin());
    std::vector<idx_t> fill(xadj.begin(), xadj.end() - 1);
    for (std::size_t e = 0; e < a.size(); ++e)
      adjncy[fill[a[e]]++] = b[e], adjncy[fill[b[e]]++] = a[e];

    std::vector<idx_t> part(n, 0);
    if (size > 1 && n > 0 && error == 0) {
      idx_t ncon = 1, nparts = size, objval = 0;
      idx_t options[METIS_NOPTIONS];
      METIS_SetDefaultOptions(options);
      options[METIS_OPTION_SEED] = 1; // reproducible partitions
      if (METIS_PartGraphKway(&n, &ncon, xadj.data(), adjncy.data(), nullptr, nullptr, nullptr,
                              &nparts, nullptr, nullptr, options, &objval, part.data()) != METIS_OK)
        error = 2;
    }
    for (std::size_t e = 0; e < a.size(); ++e) {
      cuts[0] += part[a[e]] != part[b[e]];
      cuts[1] += owner[a[e]] != owner[b[e]];
    }
    std::vector<idx_t> order(n);
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](idx_t u, idx_t w) {
      return part[u] != part[w] ? part[u] < part[w] : ids[u] < ids[w];
    });
    for (idx_t u : order)
      ordered.push_back(ids[u]), ++per_part[part[u]];
  }
  error = broadcast_value(comm, error);
  GRANPACK_CHECK(error != 1,
                 "stiffness: a backbone contact names a grain that is not on the backbone");
  GRANPACK_CHECK(error != 2, "stiffness: METIS failed to partition the contact graph");
  const auto n = broadcast_value(comm, static_cast<std::int64_t>(ordered.size()));
  broadcast_in_place(comm, cuts);
  broadcast_in_place(comm, per_part);
  ordered.resize(n);
  broadcast_in_place(comm, ordered);

  num.grains = n;
  num.ids = std::move(ordered);
  num.index.reserve(n);
  for (std::int64_t k = 0; k < n; ++k)
    num.index.emplace(num.ids[k], k);
  for (int r = 0; r < rank; ++r)
    num.first += per_part[r];
  num.local = per_part[rank];
  num.edge_cut_metis = cuts[0];
  num.edge_cut_spatial = cuts[1];
  num.metis = size > 1;
  return num;
}

} // namespace granpack
