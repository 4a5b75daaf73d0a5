#pragma once
// Broadcasts from one rank (a decision, a result computed on rank 0, a deck's text, a list of
// files), so every rank goes on with the same bytes and takes the same branches.
#include <mpi.h>

#include <ranges>
#include <string>

#include "granpack/comm/datatype.h"

namespace granpack {

/// Collective on comm: root's `value` on every rank (a flag, a count, a clock reading).
template <class T> T broadcast_value(MPI_Comm comm, T value, int root = 0) {
  MPI_Bcast(&value, mpi_count<T>(1), mpi_datatype<T>(), root, comm);
  return value;
}

/// Collective on comm: root's elements of `values` on every rank. The buffer must already have
/// root's length everywhere (a fixed size, or a length broadcast before).
template <std::ranges::contiguous_range R>
requires std::ranges::sized_range<R>
void broadcast_in_place(MPI_Comm comm, R&& values, int root = 0) {
  using T = std::ranges::range_value_t<R>;
  MPI_Bcast(std::ranges::data(values), mpi_count<T>(std::ranges::size(values)), mpi_datatype<T>(),
            root, comm);
}

/// Collective on comm: every rank ends with root's `text`.
inline void broadcast_string(MPI_Comm comm, std::string& text, int root = 0) {
  long long len = static_cast<long long>(text.size());
  MPI_Bcast(&len, 1, MPI_LONG_LONG, root, comm);
  text.resize(static_cast<std::size_t>(len));
  MPI_Bcast(text.data(), static_cast<int>(len), MPI_CHAR, root, comm);
}

} // namespace granpack
