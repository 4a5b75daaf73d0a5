#include "granpack/comm/collective_error.h"

#include <vector>

namespace granpack {

void CollectiveError::record(const std::string& message, int exit_code) {
  if (!message_.empty()) return;
  message_ = message.empty() ? std::string("unspecified error") : message;
  exit_code_ = exit_code;
}

void CollectiveError::raise_if_any(MPI_Comm comm) {
  int local[2] = {has_local() ? 1 : 0, exit_code_};
  int global[2] = {0, 0};
  MPI_Allreduce(local, global, 2, MPI_INT, MPI_MAX, comm);
  if (!global[0]) return;

  // Gather every rank's message so that all ranks throw the same text.
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  int len = static_cast<int>(message_.size());
  std::vector<int> lens(size), displs(size, 0);
  MPI_Allgather(&len, 1, MPI_INT, lens.data(), 1, MPI_INT, comm);
  for (int r = 1; r < size; ++r) displs[r] = displs[r - 1] + lens[r - 1];
  std::string all(displs.back() + lens.back(), '\0');
  MPI_Allgatherv(message_.data(), len, MPI_CHAR, all.data(), lens.data(), displs.data(), MPI_CHAR,
                 comm);
  std::string text;
  std::string previous;
  for (int r = 0; r < size; ++r) {
    if (lens[r] == 0) continue;
    std::string m = all.substr(displs[r], lens[r]);
    if (m == previous) continue;  // the same message from several ranks is said once
    if (!text.empty()) text += "\n";
    text += (size > 1 ? "[rank " + std::to_string(r) + "] " : std::string()) + m;
    previous = m;
  }
  message_.clear();
  exit_code_ = kExitOk;
  throw Error(text, global[1]);
}

}  // namespace granpack
