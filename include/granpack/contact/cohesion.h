#pragma once
// [GRC]'s short-range cohesion (eq. 4-5): a linear attraction of strength F0 and range D0.
// Across a gap 0 <= g < D0 (g = -h) the pair attracts with N^a = -F0 (1 - g/D0), normal force
// only, no damping, no tangential force: a "distant" interaction (kDistant). In contact
// (h > 0) the attraction stays constant, N^a = -F0, and adds to N^e + N^v. Coulomb and the
// rolling threshold use N^e alone ([GRC] eq. 8, 10), so a cohesive contact at its isolated
// equilibrium deflection h0 = F0/K_N (eq. 11) still resists sliding up to μF0.
#include "granpack/contact/derived_constants.h"

namespace granpack {

/// N^a = -F0 (1 - g/D0) across a gap 0 <= g < D0 ([GRC] eq. 4): Cohesion::force and the
/// batched 2D kernel (dynamics/disk_contact_batch) share it.
inline double attraction_across_gap(double f0, double d0, double gap) {
  return -f0 * (1.0 - gap / d0);
}

struct Cohesion {
  double f0 = 0; ///< maximum attractive force F0
  double d0 = 0; ///< range D0 (largest gap with an attraction)

  /// Attractive normal force N^a (<= 0) at overlap h (h < 0: gap -h).
  double force(double h) const {
    if (h > 0)
      return -f0;
    const double gap = -h;
    return gap < d0 ? attraction_across_gap(f0, d0, gap) : 0.0;
  }
  /// dN^a/dh: 0 in contact, -F0/D0 across a gap (the attraction weakens as the gap opens).
  double stiffness(double h) const {
    if (h > 0)
      return 0.0;
    return -h < d0 ? -f0 / d0 : 0.0;
  }
  /// Relative normal velocity two grains of reduced mass m* need at zero gap to escape:
  /// ½ m* v² = F0 D0 / 2, v = sqrt(F0 D0 / m*) ([GRC] eq. 7: V* sqrt(2) for unit masses).
  double escape_velocity(double reduced_mass) const;
};

inline double Cohesion::escape_velocity(double reduced_mass) const {
  return cohesive_velocity_scale(f0, d0, reduced_mass);
}

} // namespace granpack
