#pragma once
// Global reductions of scalars: the only communication stages and criteria need.
#include <mpi.h>

#include <array>
#include <cstddef>
#include <cstdint>

namespace granpack {

inline double global_sum(MPI_Comm comm, double x) {
  double y = 0;
  MPI_Allreduce(&x, &y, 1, MPI_DOUBLE, MPI_SUM, comm);
  return y;
}
inline std::int64_t global_sum(MPI_Comm comm, std::int64_t x) {
  std::int64_t y = 0;
  MPI_Allreduce(&x, &y, 1, MPI_INT64_T, MPI_SUM, comm);
  return y;
}
inline int global_max(MPI_Comm comm, int x) {
  int y = 0;
  MPI_Allreduce(&x, &y, 1, MPI_INT, MPI_MAX, comm);
  return y;
}
inline double global_max(MPI_Comm comm, double x) {
  double y = 0;
  MPI_Allreduce(&x, &y, 1, MPI_DOUBLE, MPI_MAX, comm);
  return y;
}

/// Element-wise sums and maxima of a few doubles, in one all-reduce.
template <std::size_t n> std::array<double, n> global_sum(MPI_Comm comm, std::array<double, n> x) {
  MPI_Allreduce(MPI_IN_PLACE, x.data(), static_cast<int>(n), MPI_DOUBLE, MPI_SUM, comm);
  return x;
}
template <std::size_t n> std::array<double, n> global_max(MPI_Comm comm, std::array<double, n> x) {
  MPI_Allreduce(MPI_IN_PLACE, x.data(), static_cast<int>(n), MPI_DOUBLE, MPI_MAX, comm);
  return x;
}

}  // namespace granpack
