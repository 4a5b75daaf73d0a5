#include "granpack/comm/collective_error.h"

#include <vector>

namespace granpack {

void CollectiveError::record(const std::string& message, int exit_code) {
  if (!message_.empty())
    return;
  message_ = message.empty() ? std::string("unspecified error") : message;
  exit_code_ = exit_code;
}

void CollectiveError::raise_if_any(MPI_Comm comm) {
  int local[2] = {has_local() ? 1 : 0, exit_code_};
  int global[2] = {0, 0};
  MPI_Allreduce(local, global, 2, MPI_INT, MPI_MAX, comm);
  if (!global[0])
    return;

  // Gather every rank's message so that all ranks throw the same text.
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  int len = static_cast<int>(message_.size());
  std::vector<int> lens(size), displs(size, 0);
  MPI_Allgather(&len, 1, MPI_INT, lens.data(), 1, MPI_INT, comm);
  for (int r = 1; r < size; ++r)
    displs[r] = displs[r - 1] + lens[r - 1];
  std::string all(displs.back() + lens.back(), '\0');
  MPI_Allgatherv(message_.data(), len, MPI_CHAR, all.data(), lens.data(), displs.data(), MPI_CHAR,
                 comm);
  // One distinct message that every rank saw: say it once, without rank labels. Otherwise
  // label each distinct message with the first rank that reported it.
  std::vector<std::string> messages;
  std::vector<int> first_rank;
  int failing = 0;
  for (int r = 0; r < size; ++r) {
    if (lens[r] == 0)
      continue;
    ++failing;
    std::string m = all.substr(displs[r], lens[r]);
    bool seen = false;
    for (const auto& x : messages)
      seen = seen || x == m;
    if (seen)
      continue;
    messages.push_back(m);
    first_rank.push_back(r);
  }
  std::string text;
  if (messages.size() == 1 && failing == size) {
    text = messages[0];
  } else {
    for (std::size_t k = 0; k < messages.size(); ++k) {
      if (k)
        text.push_back('\n');
      text.append("[rank ").append(std::to_string(first_rank[k])).append("] ").append(messages[k]);
    }
  }
  message_.clear();
  exit_code_ = kExitOk;
  throw Error(text, global[1]);
}

} // namespace granpack
