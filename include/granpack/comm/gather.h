#pragma once
// Gathering every grain on one rank, for the stages that run serially (the event-driven
// hard-sphere stages, docs/event-driven.md). Only those stages use it: the MD engine never
// holds all grains on one rank. Collective on comm.
#include <mpi.h>

#include <vector>

#include "granpack/core/particles.h"

namespace granpack {

/// Every rank's `mine`, concatenated in rank order, on `root` (empty elsewhere).
std::vector<double> gather_values(const std::vector<double>& mine, MPI_Comm comm, int root = 0);

/// The owned grains of every rank, sorted by global id, on `root` (empty elsewhere).
template <int dim>
std::vector<Particle<dim>> gather_particles(const ParticleStore<dim>& p, MPI_Comm comm, int root = 0);

}  // namespace granpack
