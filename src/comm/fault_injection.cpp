#include "granpack/comm/fault_injection.h"

#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "granpack/core/error.h"

namespace granpack {

namespace detail {
bool g_fault_armed = false;
} // namespace detail

namespace {

struct Fault {
  FaultPoint point = FaultPoint::kStep;
  std::string text;         // the variable's value, for the message
  std::int64_t count = 1;   // occurrence (or step number) at which to fire
  std::int64_t reached = 0; // occurrences so far in this process
};
Fault g_fault;

constexpr struct {
  const char* name;
  FaultPoint point;
} kPoints[] = {{"checkpoint_datasets", FaultPoint::kCheckpointDatasets},
               {"checkpoint_rename", FaultPoint::kCheckpointRename},
               {"collective", FaultPoint::kCollective},
               {"step", FaultPoint::kStep},
               {"hold", FaultPoint::kHold},
               {"piece", FaultPoint::kPiece},
               {"piece_hold", FaultPoint::kPieceHold}};

/// A non-negative decimal integer, the whole of `s`; -1 otherwise.
std::int64_t parse_count(const std::string& s) {
  if (s.empty() || s.size() > 18 || s.find_first_not_of("0123456789") != std::string::npos)
    return -1;
  return std::stoll(s);
}

[[noreturn]] void malformed(const std::string& value, const std::string& why) {
  throw InputError(
      "GRANPACK_FAULT=" + value + ": " + why +
      " (test-only hook: <point>[:<count>][@<rank>], point one of checkpoint_datasets, "
      "checkpoint_rename, collective, step, hold, piece, piece_hold; docs/long-jobs.md)");
}

} // namespace

void arm_fault_injection(MPI_Comm world) {
  const char* env = std::getenv("GRANPACK_FAULT");
  if (env == nullptr || *env == '\0')
    return;
  const std::string value = env;
  std::string spec = value;
  int only_rank = -1;
  if (const auto at = spec.find('@'); at != std::string::npos) {
    const std::int64_t r = parse_count(spec.substr(at + 1));
    if (r < 0 || r > 1000000)
      malformed(value, "the rank after '@' is not a rank number");
    only_rank = static_cast<int>(r);
    spec.resize(at);
  }
  std::int64_t count = 1;
  if (const auto colon = spec.find(':'); colon != std::string::npos) {
    count = parse_count(spec.substr(colon + 1));
    if (count < 1)
      malformed(value, "the count after ':' is not a positive integer");
    spec.resize(colon);
  }
  bool known = false;
  for (const auto& p : kPoints)
    if (spec == p.name)
      g_fault.point = p.point, known = true;
  if (!known)
    malformed(value, "unknown point '" + spec + "'");
  int rank = 0;
  MPI_Comm_rank(world, &rank);
  if (only_rank >= 0 && only_rank != rank)
    return;
  g_fault.text = value;
  g_fault.count = count;
  detail::g_fault_armed = true;
}

bool detail::fault_reached(FaultPoint point, std::int64_t step) {
  // kHold is reached at the same place as kStep, kPieceHold as kPiece; the caller names both.
  // These four compare the counter the caller passes, the others count their occurrences.
  const bool hold = point == FaultPoint::kHold || point == FaultPoint::kPieceHold;
  const bool by_step = hold || point == FaultPoint::kStep || point == FaultPoint::kPiece;
  if (point != g_fault.point)
    return false;
  const bool fire = by_step ? step == g_fault.count : ++g_fault.reached == g_fault.count;
  if (!fire)
    return false;
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (hold) {
    // The line a test waits for before it sends its signal.
    std::fprintf(stderr,
                 "granpack: GRANPACK_FAULT=%s: rank %d holds at %s %lld until a stop signal\n",
                 g_fault.text.c_str(), rank, point == FaultPoint::kHold ? "step" : "piece",
                 static_cast<long long>(step));
    std::fflush(stderr);
    return true;
  }
  // One line that the test reads (the fault fired where it meant), then die as kill -9 would:
  // no destructor, no flush of HDF5 or MPI state.
  char line[256];
  const int len =
      std::snprintf(line, sizeof line, "granpack: GRANPACK_FAULT=%s: rank %d killed itself\n",
                    g_fault.text.c_str(), rank);
  if (len > 0 && ::write(STDERR_FILENO, line, std::min<std::size_t>(len, sizeof line - 1)) < 0) {
    // Nothing to do: the test then misses the line and says so.
  }
  std::raise(SIGKILL);
  std::_Exit(137); // not reached
}

} // namespace granpack
