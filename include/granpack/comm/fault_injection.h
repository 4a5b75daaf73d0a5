#pragma once
// Deterministic fault injection, a test-only hook (docs/long-jobs.md, "Fault injection").
//
//   GRANPACK_FAULT=<point>[:<count>][@<rank>]
//
// makes a rank kill itself with SIGKILL (as `kill -9` or a node failure would) at a named
// point of the code, so a test of checkpoint safety kills exactly where it means to, on any
// machine load, instead of sleeping and hoping; or (point `hold`) makes it wait there for a
// stop signal, so a test of stop signals stops exactly at the step it chose. Points:
//   checkpoint_datasets  inside a checkpoint write: after the particle datasets, before the
//                        contact datasets (the temporary file is half written);
//   checkpoint_rename    after every rank has closed a complete temporary checkpoint file,
//                        before rank 0 renames it over the previous one;
//   collective           entering the all-reduce every MD step performs (the other ranks are
//                        inside it, waiting for this one);
//   step                 when the step counter (the run's, stored in checkpoints) reaches count;
//   hold                 the same place, but instead of dying the rank waits there (sleeping)
//                        until SIGTERM, SIGUSR1 or SIGINT arrives, then carries on: the run
//                        then stops at the next step, as after any stop signal. No signal
//                        within 600 s: the rank exits with code 70 (a test forgot to send it).
//   piece                between two pieces of an event-driven stage (ed_gas, ls_compress;
//                        pieces of 2000 collisions, where the stage looks at checkpoint
//                        requests), when the piece counter reaches count;
//   piece_hold           the same place, but the rank waits there for a stop signal, as hold.
// count: the count-th time this process reaches the point (default 1); for `step` and `hold`,
// the step number; for `piece` and `piece_hold`, the number of pieces the event-driven stage
// has run in this process (counted from 1 at every stage start or resume, so a count larger
// than a stage's pieces passes over it to the next event-driven stage). @rank: only that rank of
// MPI_COMM_WORLD (default: every rank that reaches the point). The variable is read once, by
// arm_fault_injection() at start-up; unset, each point costs one test of a global flag.
#include <mpi.h>

#include <cstdint>

namespace granpack {

enum class FaultPoint {
  kCheckpointDatasets,
  kCheckpointRename,
  kCollective,
  kStep,
  kHold,
  kPiece,
  kPieceHold
};

/// Collective in effect (every rank reads the same environment): parses GRANPACK_FAULT, if
/// set, and arms the point for this rank. Throws InputError (exit 2) on a malformed value.
void arm_fault_injection(MPI_Comm world);

namespace detail {
extern bool g_fault_armed;
bool fault_reached(FaultPoint point, std::int64_t step);
} // namespace detail

/// Kills this process (SIGKILL) if GRANPACK_FAULT names this point and its count is reached.
/// `step`: the step counter, for FaultPoint::kStep and kHold; the piece counter, for kPiece and
/// kPieceHold. Returns true when the caller must hold here (kHold or kPieceHold fired;
/// wait_for_stop_signal in engine/stop_signals.h), false otherwise.
inline bool fault_point(FaultPoint point, std::int64_t step = 0) {
  if (detail::g_fault_armed) [[unlikely]]
    return detail::fault_reached(point, step);
  return false;
}

} // namespace granpack
