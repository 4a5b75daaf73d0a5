#pragma once
// Prefix sums over the ranks: where this rank's slice starts in a rank-ordered whole (the
// owned grains' rows of a file written in parallel).
#include <mpi.h>

#include <algorithm>
#include <cstdint>
#include <span>

#include "granpack/comm/communicator.h"

namespace granpack {

/// Element-wise sum of `mine` over the lower ranks into `offset` (as large as `mine`): zero on
/// rank 0, where MPI_Exscan leaves the result undefined.
inline void exclusive_prefix_sum(MPI_Comm comm, std::span<const std::int64_t> mine,
                                 std::span<std::int64_t> offset) {
  MPI_Exscan(mine.data(), offset.data(), static_cast<int>(mine.size()), MPI_INT64_T, MPI_SUM, comm);
  if (rank_of(comm) == 0)
    std::fill(offset.begin(), offset.end(), 0);
}

} // namespace granpack
