#pragma once
// Global reductions (all-reduce): sums, maxima and bit unions over the ranks, of a scalar or,
// element-wise, of a buffer. Several values that belong together go in one buffer and so in one
// all-reduce: one latency instead of several, and the same order of additions as before.
#include <mpi.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <ranges>
#include <span>

#include "granpack/comm/datatype.h"

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

/// The union of every rank's flag bits (requests such as "rebuild", "checkpoint", "stop").
inline int global_bit_or(MPI_Comm comm, int bits) {
  MPI_Allreduce(MPI_IN_PLACE, &bits, 1, MPI_INT, MPI_BOR, comm);
  return bits;
}

/// A contiguous buffer of doubles, ints or int64s: a std::vector, a C array, a std::array, or a
/// std::span over an Eigen matrix's data().
template <class R>
concept ReductionBuffer = std::ranges::contiguous_range<R> && std::ranges::sized_range<R> &&
    has_mpi_datatype<std::ranges::range_value_t<R>>;

namespace detail {
template <ReductionBuffer R> void all_reduce_in_place(MPI_Comm comm, R& values, MPI_Op op) {
  using T = std::ranges::range_value_t<R>;
  MPI_Allreduce(MPI_IN_PLACE, std::ranges::data(values),
                static_cast<int>(std::ranges::size(values)), mpi_datatype<T>(), op, comm);
}
template <ReductionBuffer In, ReductionBuffer Out>
void all_reduce(MPI_Comm comm, const In& mine, Out& result, MPI_Op op) {
  using T = std::ranges::range_value_t<In>;
  static_assert(std::is_same_v<T, std::ranges::range_value_t<Out>>);
  MPI_Allreduce(std::ranges::data(mine), std::ranges::data(result),
                static_cast<int>(std::ranges::size(mine)), mpi_datatype<T>(), op, comm);
}
} // namespace detail

/// Element-wise sum (maximum) over the ranks, in place: every rank ends with the totals.
template <ReductionBuffer R> void global_sum_in_place(MPI_Comm comm, R&& values) {
  detail::all_reduce_in_place(comm, values, MPI_SUM);
}
template <ReductionBuffer R> void global_max_in_place(MPI_Comm comm, R&& values) {
  detail::all_reduce_in_place(comm, values, MPI_MAX);
}

/// Element-wise sum (maximum) of every rank's `mine` into `result` (as large as `mine`), for
/// callers that keep their own values beside the totals.
template <ReductionBuffer In, ReductionBuffer Out>
void global_sum(MPI_Comm comm, const In& mine, Out&& result) {
  detail::all_reduce(comm, mine, result, MPI_SUM);
}
template <ReductionBuffer In, ReductionBuffer Out>
void global_max(MPI_Comm comm, const In& mine, Out&& result) {
  detail::all_reduce(comm, mine, result, MPI_MAX);
}

} // namespace granpack
