#include "granpack/prep/material_law.h"

#include <cmath>
#include <numbers>

#include "granpack/core/particles.h"

namespace granpack {

double contact_duration(const ContactLawParams& m, double density, const SampleSpec& s, int dim,
                        double pressure) {
  const double a = s.diameter;
  const double d_min = s.distribution == "uniform" ? a * s.min_diameter_ratio : a;
  const double mass = dim == 3 ? HomogeneousGrain<3>::mass(density, d_min)
                               : HomogeneousGrain<2>::mass(density, d_min);
  const double m_eff = 0.5 * mass;
  double k = m.k_n;
  if (m.normal == NormalLawKind::kHertz) {
    const double e_tilde = m.young_modulus / (1 - m.poisson_ratio * m.poisson_ratio);
    const double r_eff = 0.25 * d_min;
    const double force = 5.0 * (dim == 3 ? a * a : a) * pressure;
    const double h = std::pow(1.5 * force / (e_tilde * std::sqrt(r_eff)), 2.0 / 3.0);
    k = e_tilde * std::sqrt(r_eff * h);
  }
  return std::numbers::pi * std::sqrt(m_eff / k);
}

double stiffness_number(const ContactLawParams& m, const SampleSpec& s, int dim, double pressure) {
  if (m.normal == NormalLawKind::kHertz) {
    const double e_tilde = m.young_modulus / (1 - m.poisson_ratio * m.poisson_ratio);
    return std::pow(e_tilde / pressure, 2.0 / 3.0);
  }
  return m.k_n / (std::pow(s.diameter, dim - 2) * pressure);
}

}  // namespace granpack
