#pragma once
// Gathering on every rank: each rank's count, or every rank's short list (rattler ids, a few
// divalent contacts, one eigenvector's largest entries) concatenated in rank order, for the
// small sets every rank needs whole. Collective on comm.
#include <mpi.h>

#include <cstddef>
#include <vector>

#include "granpack/comm/communicator.h"
#include "granpack/comm/datatype.h"

namespace granpack {

/// Every rank's `mine`, indexed by rank.
inline std::vector<int> allgather_value(MPI_Comm comm, int mine) {
  std::vector<int> all(static_cast<std::size_t>(size_of(comm)));
  MPI_Allgather(&mine, 1, MPI_INT, all.data(), 1, MPI_INT, comm);
  return all;
}

/// Every rank's `mine`, concatenated in rank order, on every rank. Elements travel as their MPI
/// type, or as bytes (a plain record).
template <class T> std::vector<T> allgather_concat(MPI_Comm comm, const std::vector<T>& mine) {
  const int count = mpi_count<T>(mine.size());
  const std::vector<int> counts = allgather_value(comm, count);
  std::vector<int> displs(counts.size());
  int total = 0;
  for (std::size_t r = 0; r < counts.size(); ++r)
    displs[r] = total, total += counts[r];
  std::vector<T> all(static_cast<std::size_t>(total) / std::size_t(mpi_count<T>(1)));
  const MPI_Datatype type = mpi_datatype<T>();
  MPI_Allgatherv(mine.data(), count, type, all.data(), counts.data(), displs.data(), type, comm);
  return all;
}

} // namespace granpack
