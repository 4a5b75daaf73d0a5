#pragma once
// Migration: grains that left this rank's sub-box move to their new owner, together with
// the contacts they own (a contact belongs to its smaller-id grain, see contact_store.h).
// Collective on the decomposition's communicator. Ghosts must have been cleared.
#include "granpack/comm/decomposition.h"
#include "granpack/core/system.h"

namespace granpack {

/// Wraps owned scaled positions into [0,1)^dim and sends every owned grain that is not in
/// this sub-box to its owner. Returns the number of grains this rank sent.
template <int dim> std::size_t migrate(System<dim>& sys, const Decomposition<dim>& d);

/// Redistributes an arbitrary initial split (e.g. the slices read from a file) to the
/// spatial owners. Same as migrate(); named for intent.
template <int dim> void distribute(System<dim>& sys, const Decomposition<dim>& d) {
  migrate(sys, d);
}

}  // namespace granpack
