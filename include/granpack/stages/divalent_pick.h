#pragma once
// The divalent grains of the engine's current packing, ranked for [AR] App. E's launch: the
// grains of the force-carrying backbone (iterated rattler rule, N^e above the threshold) with
// exactly two backbone contacts - the criterion `granpack stiffness` names its divalent grains
// by - sorted by decreasing contact force. Collective; the same list on every rank.
#include <vector>

#include "granpack/analysis/divalent_launch.h"
#include "granpack/core/contact_store.h"
#include "granpack/engine/md_engine.h"

namespace granpack {

/// threshold: force-carrying contacts have N^e > threshold (N).
std::vector<DivalentCandidate> divalent_candidates(RunContext<3>& ctx, const MdEngine<3>& engine,
                                                   double threshold);

/// Every contact of the current state (the keys of every rank's store), sorted: the network a
/// frozen run keeps. Collective.
std::vector<ContactKey> all_contact_keys(RunContext<3>& ctx);

} // namespace granpack
