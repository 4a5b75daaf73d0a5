#pragma once
// Gathering on one rank: every rank's values (for work done serially on rank 0, e.g. a graph
// partition or cluster analysis), or every grain, for the stages that run serially (the
// event-driven hard-sphere stages, docs/event-driven.md). The MD engine never holds all grains
// on one rank. Collective on comm.
#include <mpi.h>

#include <cstddef>
#include <vector>

#include "granpack/comm/communicator.h"
#include "granpack/comm/datatype.h"
#include "granpack/core/particles.h"

namespace granpack {

/// Every rank's `mine`, concatenated in rank order, on `root` (empty elsewhere); `origin`, if
/// given, gets on root the rank each element came from. Elements travel as their MPI type, or
/// as bytes (a record, or `how` = Transfer::bytes).
template <Transfer how = Transfer::typed, class T>
std::vector<T> gather_on_root(MPI_Comm comm, const std::vector<T>& mine, int root = 0,
                              std::vector<int>* origin = nullptr) {
  const bool on_root = rank_of(comm) == root;
  const int count = mpi_count<T, how>(mine.size());
  std::vector<int> counts(on_root ? std::size_t(size_of(comm)) : 0), displs(counts.size());
  MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, root, comm);
  std::vector<T> all;
  if (on_root) {
    int total = 0;
    for (std::size_t r = 0; r < counts.size(); ++r)
      displs[r] = total, total += counts[r];
    all.resize(static_cast<std::size_t>(total) / std::size_t(mpi_count<T, how>(1)));
    if (origin) {
      origin->clear();
      for (std::size_t r = 0; r < counts.size(); ++r)
        origin->insert(origin->end(), std::size_t(counts[r] / mpi_count<T, how>(1)), int(r));
    }
  }
  const MPI_Datatype type = mpi_datatype<T, how>();
  MPI_Gatherv(mine.data(), count, type, all.data(), counts.data(), displs.data(), type, root, comm);
  return all;
}

/// Every rank's `mine`, concatenated in rank order, on `root` (empty elsewhere).
std::vector<double> gather_values(const std::vector<double>& mine, MPI_Comm comm, int root = 0);

/// The owned grains of every rank, sorted by global id, on `root` (empty elsewhere).
template <int dim>
std::vector<Particle<dim>> gather_particles(const ParticleStore<dim>& p, MPI_Comm comm,
                                            int root = 0);

} // namespace granpack
