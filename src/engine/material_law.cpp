#include "granpack/engine/material_law.h"

#include <cmath>

#include "granpack/contact/collision_times.h"
#include "granpack/contact/contact_law_params.h"
#include "granpack/contact/derived_constants.h"
#include "granpack/core/particles.h"

namespace granpack {

double contact_duration(const ContactLawParams& m, double density, const SampleSpec& s, int dim,
                        double pressure) {
  const double a = s.diameter;
  const double d_min = s.distribution == "uniform" ? a * s.min_diameter_ratio : a;
  const double mass = dim == 3 ? HomogeneousGrain<3>::mass(density, d_min)
                               : HomogeneousGrain<2>::mass(density, d_min);
  const double m_eff = equal_grains_effective_mass(mass);
  double k = m.k_n;
  if (m.normal == NormalLawKind::kHertz) {
    const double e_tilde = e_tilde_of(m.young_modulus, m.poisson_ratio);
    const double r_eff = equal_grains_effective_radius(d_min);
    const double force = 5.0 * grain_section(dim, a) * pressure;
    k = hertz_stiffness_at_force(e_tilde, r_eff, force);
  }
  return linear_contact_duration(k, m_eff);
}

double stiffness_number(const ContactLawParams& m, const SampleSpec& s, int dim, double pressure) {
  if (m.normal == NormalLawKind::kHertz) {
    return hertz_stiffness_number(e_tilde_of(m.young_modulus, m.poisson_ratio), s.diameter, dim,
                                  pressure);
  }
  return m.k_n / (std::pow(s.diameter, dim - 2) * pressure);
}

} // namespace granpack
