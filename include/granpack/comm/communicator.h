#pragma once
// A communicator's rank and size as values (MPI returns them through pointers), and the
// sub-communicators a job splits itself into (an ensemble's groups of ranks).
#include <mpi.h>

namespace granpack {

inline int rank_of(MPI_Comm comm) {
  int r = 0;
  MPI_Comm_rank(comm, &r);
  return r;
}

inline int size_of(MPI_Comm comm) {
  int s = 1;
  MPI_Comm_size(comm, &s);
  return s;
}

/// Collective on comm: the ranks with the same `color` in a new communicator, ordered by `key`.
/// The caller frees it with free_communicator.
inline MPI_Comm split_communicator(MPI_Comm comm, int color, int key) {
  MPI_Comm part;
  MPI_Comm_split(comm, color, key, &part);
  return part;
}

/// Collective on comm: frees a communicator from split_communicator (comm is then MPI_COMM_NULL).
inline void free_communicator(MPI_Comm& comm) {
  MPI_Comm_free(&comm);
}

} // namespace granpack
