#pragma once
// Normal viscous damping ([AR] eq. 4-5, [GRC] eq. 6): N^v = α ḣ with
// α = ζ · 2 sqrt(m* K_N(h)), a fraction ζ of the critical damping of the linear spring K_N(h)
// carrying the reduced mass m*. For equal masses m (m* = m/2): α = ζ sqrt(2 m K_N) (eq. 5).
// Active only in true contact (h > 0). By default the viscous force may make the total
// N^e + N^v attractive at the end of a damped collision, as [GRC] write it ("opposes the normal
// relative receding velocity as long as the contact persists"); [AR] do not say. With
// `tension = false` it is limited to N^v >= -N^e (no pull), as many DEM codes do: a switch for
// the controlled experiments of docs/reproduction.md.
#include <algorithm>
#include <cmath>

namespace granpack {

/// α = 2ζ sqrt(m* K_N) given 2ζ: the formula NormalDamping and the batched kernel
/// (dynamics/hertz_mindlin_batch, which holds 2ζ) share.
inline double viscous_coefficient(double two_zeta, double m_eff, double k_n) {
  return two_zeta * std::sqrt(m_eff * k_n);
}

/// N^e + N^v as applied: unchanged when the damping may pull (`tension`), else at least 0
/// (N^v limited to -N^e). Applied to the sum, so that the default path computes N^e + N^v
/// exactly as before the switch existed (same operations, same rounding, fused or not).
/// Shared by ContactLaw::force and the batch.
inline double applied_elastic_viscous_force(double n_elastic_plus_viscous, bool tension) {
  return tension ? n_elastic_plus_viscous : std::max(n_elastic_plus_viscous, 0.0);
}

struct NormalDamping {
  double zeta = 0;     ///< fraction of critical damping, in [0, 1)
  bool tension = true; ///< N^e + N^v may be < 0 (false: N^v limited to -N^e)

  /// α(h) for reduced mass m* and current normal stiffness K_N(h).
  double coefficient(double m_eff, double k_n) const {
    return zeta > 0 ? viscous_coefficient(2.0 * zeta, m_eff, k_n) : 0.0;
  }
};

} // namespace granpack
