#pragma once
// The contact network of the run's state as written into configuration files (the /network
// group, shown by the XDMF sidecar: docs/visualisation.md): a ghost layer of its own is built
// around the owned grains so that each contact finds both grains, the kernel of
// analysis/contact_network computes the segments and forces, and the per-grain sums of ghosts
// are added into their owners. Collective on ctx.world.
#include <optional>

#include "granpack/analysis/contact_network.h"
#include "granpack/engine/run_context.h"

namespace granpack {

/// The fields of `contacts` (this rank's, in this order) over the owned grains of
/// ctx.system, per grain in the owned order. std::nullopt on every rank when some rank cannot
/// place a contact (a state without positions for both grains of a pair within the ghost
/// layer, or sub-boxes narrower than the layer): the file is then written without /network.
template <int dim>
std::optional<NetworkFields<dim>> network_fields(const RunContext<dim>& ctx,
                                                 const ContactStore<dim>& contacts);

extern template std::optional<NetworkFields<2>> network_fields<2>(const RunContext<2>&,
                                                                  const ContactStore<2>&);
extern template std::optional<NetworkFields<3>> network_fields<3>(const RunContext<3>&,
                                                                  const ContactStore<3>&);

} // namespace granpack
