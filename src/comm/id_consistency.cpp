#include "granpack/comm/id_consistency.h"

#include <algorithm>
#include <limits>
#include <vector>

namespace granpack {

namespace {

/// `values` sent to the rank value mod P; returns what this rank receives.
std::vector<std::int64_t> route_by_id(MPI_Comm comm, const std::vector<std::int64_t>& values) {
  int size = 1;
  MPI_Comm_size(comm, &size);
  std::vector<int> send_counts(size, 0), recv_counts(size, 0);
  auto owner = [&](std::int64_t v) { return static_cast<int>(((v % size) + size) % size); };
  for (const auto v : values)
    ++send_counts[owner(v)];
  MPI_Alltoall(send_counts.data(), 1, MPI_INT, recv_counts.data(), 1, MPI_INT, comm);
  std::vector<int> send_displ(size, 0), recv_displ(size, 0);
  for (int r = 1; r < size; ++r) {
    send_displ[r] = send_displ[r - 1] + send_counts[r - 1];
    recv_displ[r] = recv_displ[r - 1] + recv_counts[r - 1];
  }
  std::vector<std::int64_t> send(values.size());
  std::vector<int> fill = send_displ;
  for (const auto v : values)
    send[fill[owner(v)]++] = v;
  std::vector<std::int64_t> recv(
      static_cast<std::size_t>(recv_displ[size - 1] + recv_counts[size - 1]));
  MPI_Alltoallv(send.data(), send_counts.data(), send_displ.data(), MPI_INT64_T, recv.data(),
                recv_counts.data(), recv_displ.data(), MPI_INT64_T, comm);
  return recv;
}

} // namespace

std::string find_id_inconsistency(MPI_Comm comm, std::span<const std::int64_t> ids,
                                  std::span<const std::int64_t> first,
                                  std::span<const std::int64_t> second) {
  constexpr std::int64_t kNone = std::numeric_limits<std::int64_t>::max();
  std::vector<std::int64_t> mine = route_by_id(comm, {ids.begin(), ids.end()});
  std::sort(mine.begin(), mine.end());
  // [0]: the smallest duplicated id, [1]: the smallest contact end that names no grain.
  std::int64_t worst[2] = {kNone, kNone};
  for (std::size_t i = 1; i < mine.size(); ++i)
    if (mine[i] == mine[i - 1]) {
      worst[0] = mine[i];
      break;
    }
  std::vector<std::int64_t> ends(first.begin(), first.end());
  ends.insert(ends.end(), second.begin(), second.end());
  for (const auto e : route_by_id(comm, ends))
    if (!std::binary_search(mine.begin(), mine.end(), e))
      worst[1] = std::min(worst[1], e);
  MPI_Allreduce(MPI_IN_PLACE, worst, 2, MPI_INT64_T, MPI_MIN, comm);
  if (worst[0] != kNone) {
    // How often: counted by the rank that holds the id, then shared.
    std::int64_t times = std::count(mine.begin(), mine.end(), worst[0]);
    MPI_Allreduce(MPI_IN_PLACE, &times, 1, MPI_INT64_T, MPI_MAX, comm);
    return "particle id " + std::to_string(worst[0]) + " appears " + std::to_string(times) +
           " times in /particles/id (ids must be unique)";
  }
  if (worst[1] != kNone)
    return "a contact names grain " + std::to_string(worst[1]) +
           ", which /particles/id does not hold";
  return "";
}

} // namespace granpack
