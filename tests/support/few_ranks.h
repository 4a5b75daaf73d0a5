#pragma once
// Preparing the packing an MPI test works on: on every rank when there are one or two, on
// rank 0 alone when there are more. Why: the oversubscribed cases (3 and 4 ranks on two cores)
// are there to test how analyze and stiffness share their work, and the engine's own 3- and
// 4-rank results are tested by mpi.engine. Oversubscribed ranks yield their core whenever they
// wait (OMPI_MCA_mpi_yield_when_idle), so a compression run on several of them waits a
// scheduler slice in the collectives of every step whenever anything else runs: the
// 17 400-step FCC compression took 90-220 s at 3 ranks, and 45-55 s even on 2 of them, beside
// two background jobs; on one rank it has no collective to wait in (2 s). The other ranks wait
// asleep rather than spinning in MPI, so that rank 0 has a core.
#include <mpi.h>

#include <chrono>
#include <thread>

#include "granpack/app/run_deck.h"
#include "granpack/comm/communicator.h"

namespace granpack::test {

/// Completes a nonblocking request by testing it every millisecond, sleeping in between.
inline void wait_asleep(MPI_Request& request) {
  int done = 0;
  for (MPI_Test(&request, &done, MPI_STATUS_IGNORE); !done;
       MPI_Test(&request, &done, MPI_STATUS_IGNORE))
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
}

/// Runs the deck on all ranks of MPI_COMM_WORLD if they are at most two, else on rank 0 alone
/// (a communicator of its own); every rank returns run_deck's exit code on rank 0.
inline int run_deck_on_few_ranks(const RunOptions& options) {
  const int rank = rank_of(MPI_COMM_WORLD);
  const bool runs = size_of(MPI_COMM_WORLD) <= 2 || rank == 0;
  MPI_Comm group = split_communicator(MPI_COMM_WORLD, runs ? 0 : MPI_UNDEFINED, rank);
  int code = 0;
  if (runs) {
    code = run_deck(group, options);
    free_communicator(group);
  }
  MPI_Request request;
  MPI_Ibcast(&code, 1, MPI_INT, 0, MPI_COMM_WORLD, &request);
  wait_asleep(request);
  return code;
}

} // namespace granpack::test
