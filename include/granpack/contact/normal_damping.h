#pragma once
// Normal viscous damping ([AR] eq. 4-5, [GRC] eq. 6): N^v = α ḣ with
// α = ζ · 2 sqrt(m* K_N(h)), a fraction ζ of the critical damping of the linear spring K_N(h)
// carrying the reduced mass m*. For equal masses m (m* = m/2): α = ζ sqrt(2 m K_N) (eq. 5).
// Active only in true contact (h > 0); the viscous force may be attractive (not clipped).
#include <cmath>

namespace granpack {

/// α = 2ζ sqrt(m* K_N) given 2ζ: the formula NormalDamping and the batched kernel
/// (dynamics/hertz_mindlin_batch, which holds 2ζ) share.
inline double viscous_coefficient(double two_zeta, double m_eff, double k_n) {
  return two_zeta * std::sqrt(m_eff * k_n);
}

struct NormalDamping {
  double zeta = 0; ///< fraction of critical damping, in [0, 1)

  /// α(h) for reduced mass m* and current normal stiffness K_N(h).
  double coefficient(double m_eff, double k_n) const {
    return zeta > 0 ? viscous_coefficient(2.0 * zeta, m_eff, k_n) : 0.0;
  }
};

} // namespace granpack
