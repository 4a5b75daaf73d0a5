#pragma once
// Broadcasts of variable-length data read on one rank (a deck's text, a list of files), so
// every rank works on the same bytes.
#include <mpi.h>

#include <string>

namespace granpack {

/// Collective on comm: every rank ends with root's `text`.
inline void broadcast_string(MPI_Comm comm, std::string& text, int root = 0) {
  long long len = static_cast<long long>(text.size());
  MPI_Bcast(&len, 1, MPI_LONG_LONG, root, comm);
  text.resize(static_cast<std::size_t>(len));
  MPI_Bcast(text.data(), static_cast<int>(len), MPI_CHAR, root, comm);
}

}  // namespace granpack
