#include "granpack/contact/contact_law_params.h"

#include <cmath>

#include "granpack/contact/derived_constants.h"
#include "granpack/core/error.h"

namespace granpack {

namespace {
void require(bool ok, const char* what) {
  if (!ok)
    throw InputError(std::string("contact law: ") + what);
}
} // namespace

template <int dim> ContactLaw<dim> make_contact_law(const ContactLawParams& p) {
  ContactLaw<dim> law;
  const double nu = p.poisson_ratio;
  switch (p.normal) {
  case NormalLawKind::kHertz:
    require(std::isfinite(p.young_modulus) && p.young_modulus > 0,
            "Hertz needs a Young modulus E > 0");
    require(std::isfinite(nu) && nu > -1 && nu < 0.5, "Poisson ratio must be in (-1, 0.5)");
    law.normal = HertzNormal{e_tilde_of(p.young_modulus, nu)};
    break;
  case NormalLawKind::kLinear:
    require(std::isfinite(p.k_n) && p.k_n > 0, "linear normal law needs K_N > 0");
    law.normal = LinearNormal{p.k_n};
    break;
  }
  switch (p.tangential) {
  case TangentialStiffnessKind::kMindlin:
    require(std::isfinite(nu) && nu > -1 && nu < 0.5,
            "Mindlin tangential stiffness needs a Poisson ratio in (-1, 0.5)");
    law.tangential = TangentialElasticity::mindlin(nu);
    break;
  case TangentialStiffnessKind::kRatio:
    require(std::isfinite(p.k_t_ratio) && p.k_t_ratio >= 0, "K_T/K_N must be >= 0");
    law.tangential = TangentialElasticity::ratio(p.k_t_ratio);
    break;
  case TangentialStiffnessKind::kConstant:
    require(std::isfinite(p.k_t) && p.k_t >= 0, "constant K_T must be >= 0");
    law.tangential = TangentialElasticity::constant(p.k_t);
    break;
  }
  law.tangential.walton_rescaling = p.walton_rescaling;
  require(p.damping_ratio >= 0 && p.damping_ratio < 1, "damping ratio zeta must be in [0, 1)");
  law.damping = NormalDamping{p.damping_ratio, p.damping_tension};
  require(p.friction >= 0, "friction coefficient mu must be >= 0 (inf allowed)"); // NaN fails
  law.friction = CoulombFriction{p.friction};
  require(std::isfinite(p.cohesion_force) && p.cohesion_force >= 0,
          "cohesion force F0 must be finite and >= 0");
  require(std::isfinite(p.cohesion_range) && p.cohesion_range >= 0,
          "cohesion range D0 must be finite and >= 0");
  if (p.cohesion_force > 0 || p.cohesion_range > 0) {
    // A zero range would make the attraction jump from -F0 to 0 as the contact opens (no
    // escape velocity, eq. 7); a range without a force is a typo.
    require(p.cohesion_force > 0 && p.cohesion_range > 0,
            "cohesion needs both a force F0 > 0 and a range D0 > 0");
    law.cohesion = Cohesion{p.cohesion_force, p.cohesion_range};
  }
  require(std::isfinite(p.rolling_stiffness) && p.rolling_stiffness >= 0,
          "rolling stiffness K_r must be finite and >= 0");
  require(p.rolling_friction >= 0, "rolling friction mu_r must be >= 0 (inf allowed)");
  require(p.rolling_damping >= 0 && p.rolling_damping < 1,
          "rolling damping zeta_r must be in [0, 1)");
  if (p.rolling_stiffness > 0 || p.rolling_friction > 0 || p.rolling_damping > 0) {
    require(p.rolling_stiffness > 0,
            "rolling friction mu_r or damping zeta_r > 0 needs a rolling stiffness K_r > 0");
    law.rolling = RollingResistance{p.rolling_stiffness, p.rolling_friction, p.rolling_damping};
  }
  return law;
}

template ContactLaw<2> make_contact_law<2>(const ContactLawParams&);
template ContactLaw<3> make_contact_law<3>(const ContactLawParams&);

} // namespace granpack
