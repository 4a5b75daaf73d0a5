#pragma once
// Errors known on one rank only (a NaN, a lost grain, an unreadable slice of a file) must stop
// every rank with the same message, or the others hang in the next collective call.
// Record them locally, then call raise_if_any() at a sync point: it is collective on `comm`
// and throws the same Error (with every rank's message) on all ranks.
#include <mpi.h>

#include <string>

#include "granpack/core/error.h"

namespace granpack {

class CollectiveError {
public:
  /// Remembers a local failure and the exit code it should map to (first one wins).
  void record(const std::string& message, int exit_code = kExitFailure);
  bool has_local() const { return !message_.empty(); }
  /// Collective on comm. If any rank recorded an error, throws on every rank an Error whose
  /// text lists each failing rank's message and whose exit code is the largest recorded.
  void raise_if_any(MPI_Comm comm);

private:
  std::string message_;
  int exit_code_ = kExitOk;
};

/// Runs f() on every rank; an exception thrown on some ranks only is turned into the same
/// exception on all ranks (collective on comm). Use around code that may fail locally.
template <class F> void collectively(MPI_Comm comm, F&& f) {
  CollectiveError err;
  try {
    f();
  } catch (const Error& e) {
    err.record(e.what(), e.exit_code());
  } catch (const std::exception& e) {
    err.record(e.what(), kExitFailure);
  }
  err.raise_if_any(comm);
}

} // namespace granpack
