#pragma once
// Waiting for every rank: to time a collective section from a common start, or at the end of
// a job whose ranks finish at different times.
#include <mpi.h>

#include <chrono>
#include <thread>

namespace granpack {

/// Returns on each rank once every rank of comm got here.
inline void barrier(MPI_Comm comm) {
  MPI_Barrier(comm);
}

/// The wall clock (MPI_Wtime) once every rank of comm got here: two readings bracket the
/// slowest rank's work, not this rank's.
inline double synchronized_wtime(MPI_Comm comm) {
  MPI_Barrier(comm);
  return MPI_Wtime();
}

/// A barrier that sleeps while it waits instead of spinning in MPI: a group that finished
/// early must not take a core from the groups still running (ranks may outnumber cores).
inline void idle_barrier(MPI_Comm comm,
                         std::chrono::milliseconds poll = std::chrono::milliseconds(50)) {
  MPI_Request request;
  MPI_Ibarrier(comm, &request);
  int done = 0;
  while (true) {
    MPI_Test(&request, &done, MPI_STATUS_IGNORE);
    if (done)
      break;
    std::this_thread::sleep_for(poll);
  }
}

} // namespace granpack
