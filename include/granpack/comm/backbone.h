#pragma once
// The force-carrying backbone of a distributed packing: the iterative rattler rule of [AR]
// sec. III B run across ranks (a contact's two grains may live on two ranks). Used by the
// stages (report metrics) and by `granpack analyze`. Collective on the decomposition.
#include <cstdint>
#include <vector>

#include "granpack/analysis/coordination.h"
#include "granpack/comm/halo.h"

namespace granpack {

struct StateMetrics {
  double z = 0, z_star = 0, x0 = 0;
  double x2 = 0; ///< fraction of all grains with exactly 2 backbone contacts
  double z2 = 0; ///< Z(2) = <N^2>/<N>^2 over the backbone contacts ([AR] eq. 27); 0 if none
  std::int64_t backbone_contacts = 0, rattlers = 0, n = 0;
};

struct Backbone {
  std::vector<std::uint8_t> rattler; ///< per local particle (ghost flags are copies)
  std::vector<double> counts;        ///< backbone contacts per owned particle
  StateMetrics metrics;
};

/// `carrying`: this rank's force-carrying contacts by local index (ghosts included).
/// min_contacts: min_backbone_contacts(dim, μ) of contact/derived_constants.h.
template <int dim>
Backbone find_backbone(const ParticleStore<dim>& p, const Halo<dim>& halo,
                       const Decomposition<dim>& d, const std::vector<CarryingContact>& carrying,
                       int min_contacts);

} // namespace granpack
