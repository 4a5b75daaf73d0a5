#pragma once
// Stage 2 of the bond-orientational order across ranks (docs/analysis-order.md): the owners'
// normalised q6 copied to the ranks that hold their grains as ghosts, so that both ends of a
// bond decide eq. (34) of [AR] with the same numbers. Used by `granpack analyze` (order
// section) and by the /network crystalline flags (engine/network_fields). Collective on
// d.comm().
#include <vector>

#include "granpack/analysis/bond_order.h"
#include "granpack/comm/halo.h"

namespace granpack {

/// `q6`: the l = 6 local order of every owned grain of `p`, in the owned order. Returns the
/// table of the normalised q6 of every local grain (owned and ghosts, one entry per id).
QBarTable exchange_qbar(const ParticleStore<3>& p, const std::vector<LocalBondOrder>& q6,
                        const Halo<3>& halo, const Decomposition<3>& d);

} // namespace granpack
