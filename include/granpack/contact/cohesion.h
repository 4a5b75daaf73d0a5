#pragma once
// Slot for [GRC]'s cohesion (eq. 4-5): attraction of strength F0 and range D0, constant -F0
// in contact, distant interactions (normal force only) across gaps 0 < -h < D0, flagged
// kDistant. NOT IMPLEMENTED YET: the factory refuses it (NotImplemented) and
// ContactLaw::force marks where it plugs in. Only interaction range is already honoured.

namespace granpack {

struct Cohesion {
  double f0 = 0;  ///< maximum attractive force F0
  double d0 = 0;  ///< range D0 (largest gap with an attraction)
};

}  // namespace granpack
