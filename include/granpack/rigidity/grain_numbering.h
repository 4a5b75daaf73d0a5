#pragma once
// Which rank owns which backbone grain's rows in the distributed matrices: METIS on the
// backbone contact graph, the grains of part r numbered contiguously and owned by rank r.
// The grains themselves stay where the spatial decomposition put them; only the PETSc row
// ownership follows the partition (off-rank blocks travel in MatAssembly).
//
// The partition is computed by serial METIS on rank 0 from the gathered contact graph
// (n* vertices, N_c edges: a few hundred kB at n = 32000; ParMETIS is not in the build) and
// the numbering is broadcast: this is the one O(n) array every rank holds. Collective.
#include <mpi.h>

#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

#include "granpack/core/vec.h"

namespace granpack {

struct GrainNumbering {
  std::unordered_map<GlobalId, std::int64_t> index; ///< backbone grain id -> global index
  std::vector<GlobalId> ids;                        ///< global index -> grain id
  std::int64_t grains = 0;                          ///< n*
  std::int64_t first = 0, local = 0;                ///< this rank's index range
  std::int64_t edge_cut_metis = 0;   ///< backbone contacts whose grains are in two parts
  std::int64_t edge_cut_spatial = 0; ///< same for the spatial decomposition's ownership
  bool metis = false;                ///< false on one rank (nothing to partition)
};

/// `owned_grains`: ids of this rank's owned backbone grains; `edges`: this rank's backbone
/// contacts as id pairs (each contact on one rank). Collective on comm.
GrainNumbering number_backbone_grains(MPI_Comm comm, const std::vector<GlobalId>& owned_grains,
                                      const std::vector<std::pair<GlobalId, GlobalId>>& edges);

} // namespace granpack
