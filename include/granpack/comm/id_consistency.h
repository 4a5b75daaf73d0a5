#pragma once
// Global checks of the grain ids a file's rows hold, spread over the ranks that read them
// (every rank reads a slice of /particles and /contacts): no id twice, and no contact naming
// a grain the file does not hold. Each id and each contact end goes to the rank id mod P
// (one all-to-all), so the memory per rank stays O(n/P) at any size. Collective on comm.
#include <mpi.h>

#include <cstdint>
#include <span>
#include <string>

namespace granpack {

/// "" when every id of `ids` (over all ranks) is unique and every entry of `first` and
/// `second` is one of them; otherwise one message, the same on every rank, naming the
/// smallest offending id: "particle id 17 appears 2 times" or "a contact names grain 9999,
/// which /particles/id does not hold".
std::string find_id_inconsistency(MPI_Comm comm, std::span<const std::int64_t> ids,
                                  std::span<const std::int64_t> first,
                                  std::span<const std::int64_t> second);

} // namespace granpack
