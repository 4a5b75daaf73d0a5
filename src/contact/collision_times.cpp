#include "granpack/contact/collision_times.h"

#include <cmath>
#include <numbers>

namespace granpack {

double hertz_duration_constant() {
  // 2 ∫_0^1 (1 - x^p)^{-1/2} dx = 2 Γ(1/p) Γ(1/2) / (p Γ(1/p + 1/2)), p = 5/2.
  const double p = 2.5;
  return 2.0 * std::tgamma(1.0 / p) * std::sqrt(std::numbers::pi) /
         (p * std::tgamma(1.0 / p + 0.5));
}

double hertz_max_overlap(double e_tilde, double r_eff, double m_eff, double v) {
  const double e_star = 0.5 * e_tilde;
  return std::pow(15.0 * m_eff * v * v / (16.0 * e_star * std::sqrt(r_eff)), 0.4);
}

double hertz_contact_duration(double e_tilde, double r_eff, double m_eff, double v) {
  return hertz_duration_constant() * hertz_max_overlap(e_tilde, r_eff, m_eff, v) / v;
}

double linear_contact_duration(double k, double m_eff) {
  return std::numbers::pi * std::sqrt(m_eff / k);
}

double damped_linear_contact_duration(double k, double m_eff, double zeta) {
  return linear_contact_duration(k, m_eff) / std::sqrt(1.0 - zeta * zeta);
}

double linear_restitution(double zeta) {
  return std::exp(-zeta * std::numbers::pi / std::sqrt(1.0 - zeta * zeta));
}

double linear_critical_time_step(double k, double m_eff) {
  return 2.0 * std::sqrt(m_eff / k);
}

} // namespace granpack
