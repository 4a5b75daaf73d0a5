#pragma once
// [GRC]'s rolling resistance (eq. 9-10): an elastic-plastic moment against the relative
// rotation of two grains in contact, the rotational analogue of tangential elasticity and
// Coulomb friction. The elastic relative rotation δθ (ContactState::rolling) grows with the
// relative spin ω_j - ω_i; the moment on j is Γ^r = -K_r δθ (on i: +K_r δθ) and
// |Γ^r| <= μ_r N^e: beyond it δθ is held on the threshold (kRollingPlastic).
// The paper writes Γ^r = K_r δθ; the minus makes the moment restoring with δθ measured as
// the rotation of j relative to i. In 3D only the rolling components (normal to n) resist;
// pivoting (spin about n) is left free, and δθ is transported with the contact like T.
//
// Optional rolling damping (NOT in [GRC]): a viscous moment -η_r (ω_j - ω_i) (rolling part)
// with η_r = ζ_r 2 R* sqrt(m* K_r), the fraction ζ_r of the critical damping of the rolling
// spring K_r for a pair of inertia m* R*². [GRC]'s only dissipation is the normal viscous
// force; with rolling springs it leaves rocking modes that decay so slowly that packings do
// not meet the II D criteria in affordable times (docs/contact-law.md). Being viscous, the
// moment is left out of the static moments of the equilibrium criteria.
#include <algorithm>
#include <cmath>

#include "granpack/core/vec.h"

namespace granpack {

// The formulas of the rolling sub-model, one inline function each: RollingResistance and the
// batched 2D kernel (dynamics/disk_contact_batch) both call them.

/// η_r = ζ_r 2 R* sqrt(m* K_r).
inline double rolling_viscosity(double zeta_r, double k_r, double effective_mass,
                                double effective_radius) {
  return zeta_r * 2.0 * effective_radius * std::sqrt(effective_mass * k_r);
}
/// The threshold μ_r N^e on |K_r δθ| ([GRC] eq. 10; N^e alone, never negative).
inline double rolling_limit(double mu_r, double normal_elastic) {
  return mu_r * std::max(normal_elastic, 0.0);
}
/// |K_r δθ|² = m2 beyond the threshold (also for a NaN limit: μ_r = inf with N^e = 0).
inline bool beyond_rolling_limit(double m2, double limit) {
  return !(m2 <= limit * limit);
}

struct RollingResistance {
  double k_r = 0;     ///< rolling stiffness K_r (moment per radian)
  double mu_r = 0;    ///< rolling friction μ_r (a length): |Γ^r| <= μ_r N^e
  double damping = 0; ///< ζ_r, fraction of the critical rolling damping (0: [GRC])

  /// η_r = ζ_r 2 R* sqrt(m* K_r).
  double viscosity(double effective_mass, double effective_radius) const {
    return rolling_viscosity(damping, k_r, effective_mass, effective_radius);
  }

  /// Adds the relative rotation increment d_theta to the elastic rotation theta, then
  /// projects it back on |K_r θ| <= μ_r N^e. Returns true when the limit was reached.
  template <int dim>
  bool update(RotVec<dim>& theta, const RotVec<dim>& d_theta, double normal_elastic) const {
    theta += d_theta;
    const double limit = rolling_limit(mu_r, normal_elastic);
    const double m2 = k_r * k_r * theta.squaredNorm();
    if (!beyond_rolling_limit(m2, limit))
      return false;
    theta = limit > 0 ? RotVec<dim>(theta * (limit / std::sqrt(m2))) : RotVec<dim>::Zero();
    return true;
  }
};

} // namespace granpack
