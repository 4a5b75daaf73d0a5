#pragma once
// The MPI datatype a C++ element travels as, so the helpers of comm/ pick it from the element
// type and a caller cannot pair a buffer with the wrong MPI type or count.
#include <mpi.h>

#include <cstddef>
#include <cstdint>
#include <type_traits>

namespace granpack {

/// The element types with an MPI datatype of their own (arithmetic, so reductions work on them).
template <class T>
inline constexpr bool has_mpi_datatype =
    std::is_same_v<T, double> || std::is_same_v<T, int> || std::is_same_v<T, std::int64_t> ||
    std::is_same_v<T, unsigned long long> || std::is_same_v<T, char>;

/// How a vector's elements travel: `typed` as the element's MPI datatype where it has one,
/// else as bytes (a plain record); `bytes` always as bytes. Either moves the same
/// bits; callers keep the choice the code made before comm/ took the call over.
enum class Transfer { typed, bytes };

template <class T, Transfer how = Transfer::typed> constexpr bool travels_as_bytes() {
  // Trivially copy-constructible rather than trivially copyable: std::pair of ids has a
  // user-provided assignment but its bytes are its value all the same.
  static_assert(std::is_trivially_copy_constructible_v<T> && std::is_trivially_destructible_v<T>,
                "only elements whose bytes are their value travel as memory");
  return how == Transfer::bytes || !has_mpi_datatype<T>;
}

template <class T, Transfer how = Transfer::typed> MPI_Datatype mpi_datatype() {
  if constexpr (travels_as_bytes<T, how>())
    return MPI_BYTE;
  else if constexpr (std::is_same_v<T, double>)
    return MPI_DOUBLE;
  else if constexpr (std::is_same_v<T, int>)
    return MPI_INT;
  else if constexpr (std::is_same_v<T, std::int64_t>)
    return MPI_INT64_T;
  else if constexpr (std::is_same_v<T, unsigned long long>)
    return MPI_UNSIGNED_LONG_LONG;
  else
    return MPI_CHAR;
}

/// MPI counts of `n` elements: elements, or bytes for those that travel as bytes.
template <class T, Transfer how = Transfer::typed> constexpr int mpi_count(std::size_t n) {
  return static_cast<int>(travels_as_bytes<T, how>() ? n * sizeof(T) : n);
}

} // namespace granpack
