#pragma once
// The simulated state one rank holds: its share of the grains, the contacts it owns, the cell
// (identical on every rank) and the clock. MPI-free: the decomposition lives in comm/.
#include <cstdint>

#include "granpack/core/cell.h"
#include "granpack/core/contact_store.h"
#include "granpack/core/particles.h"

namespace granpack {

template <int dim> struct System {
  Cell<dim> cell;
  ParticleStore<dim> particles;
  ContactStore<dim> contacts;
  double time = 0.0;     ///< simulated time, s
  std::int64_t step = 0; ///< time steps since the start of the run
};

} // namespace granpack
