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

/// Redistributes an arbitrary initial split (e.g. the slices read from a file, where a
/// contact need not sit on the rank of its grains) to the spatial owners: grains by
/// migrate(), then every contact to the rank owning its first grain, through a directory
/// rank (id mod ranks) that learns each grain's owner. Throws if a contact names a grain
/// that does not exist.
template <int dim> void distribute(System<dim>& sys, const Decomposition<dim>& d);

} // namespace granpack
