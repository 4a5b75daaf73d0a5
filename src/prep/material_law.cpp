#include "granpack/prep/material_law.h"

#include <cmath>

#include "granpack/contact/collision_times.h"
#include "granpack/contact/contact_law_params.h"
#include "granpack/contact/derived_constants.h"
#include "granpack/core/particles.h"

namespace granpack {

template <int dim> ContactLaw<dim> contact_law_of(const MaterialSpec& m) {
  ContactLawParams p;
  if (m.normal_law == "hertz") {
    p.normal = NormalLawKind::kHertz;
    p.young_modulus = m.young_modulus;
    p.poisson_ratio = m.poisson_ratio;
    p.tangential = TangentialStiffnessKind::kMindlin;
  } else {
    p.normal = NormalLawKind::kLinear;
    p.k_n = m.normal_stiffness;
    p.tangential = TangentialStiffnessKind::kRatio;
    p.k_t_ratio = m.tangential_stiffness_ratio;
  }
  p.damping_ratio = m.damping;
  p.friction = m.friction;
  p.cohesion_force = m.cohesion_force;
  p.cohesion_range = m.cohesion_range;
  p.rolling_stiffness = m.rolling_stiffness;
  p.rolling_friction = m.rolling_friction;
  p.rolling_damping = m.rolling_damping;
  return make_contact_law<dim>(p);
}

double contact_duration(const MaterialSpec& m, const SampleSpec& s, int dim, double pressure) {
  const double a = s.diameter;
  const double d_min = s.distribution == "uniform" ? a * s.min_diameter_ratio : a;
  const double mass = dim == 3 ? HomogeneousGrain<3>::mass(m.density, d_min)
                               : HomogeneousGrain<2>::mass(m.density, d_min);
  const double m_eff = equal_grains_effective_mass(mass);
  double k = m.normal_stiffness;
  if (m.normal_law == "hertz") {
    const double e_tilde = e_tilde_of(m.young_modulus, m.poisson_ratio);
    const double r_eff = equal_grains_effective_radius(d_min);
    const double force = 5.0 * grain_section(dim, a) * pressure;
    k = hertz_stiffness_at_force(e_tilde, r_eff, force);
  }
  return linear_contact_duration(k, m_eff);
}

double stiffness_number(const MaterialSpec& m, const SampleSpec& s, int dim, double pressure) {
  if (m.normal_law == "hertz") {
    return hertz_stiffness_number(e_tilde_of(m.young_modulus, m.poisson_ratio), pressure);
  }
  return m.normal_stiffness / (std::pow(s.diameter, dim - 2) * pressure);
}

template ContactLaw<2> contact_law_of<2>(const MaterialSpec&);
template ContactLaw<3> contact_law_of<3>(const MaterialSpec&);

}  // namespace granpack
