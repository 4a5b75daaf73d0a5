#pragma once
// Plain parameters of a contact law, as a deck fills them, and the factory that validates
// them and builds ContactLaw<dim>. Bad values throw InputError.
#include <limits>

#include "granpack/contact/contact_law.h"

namespace granpack {

enum class NormalLawKind { kHertz, kLinear };

struct ContactLawParams {
  NormalLawKind normal = NormalLawKind::kHertz;
  double young_modulus = 0; ///< E (Hertz)
  double poisson_ratio = 0; ///< ν (Hertz; also kMindlin tangential)
  double k_n = 0;           ///< linear normal stiffness K_N
  TangentialStiffnessKind tangential = TangentialStiffnessKind::kMindlin;
  double k_t = 0;              ///< kConstant: K_T
  double k_t_ratio = 0;        ///< kRatio: K_T / K_N
  double damping_ratio = 0;    ///< ζ in [0, 1)
  bool damping_tension = true; ///< NormalDamping::tension
  double friction = 0;         ///< μ in [0, +inf]
  bool walton_rescaling = true;
  // [GRC] parts, off when 0: cohesion needs F0 > 0 and D0 > 0; rolling resistance K_r > 0
  // (μ_r >= 0, inf allowed).
  double cohesion_force = 0, cohesion_range = 0;      ///< F0, D0
  double rolling_stiffness = 0, rolling_friction = 0; ///< K_r, μ_r
  double rolling_damping = 0; ///< ζ_r in [0, 1) (not in [GRC]; needs K_r > 0)
  friend bool operator==(const ContactLawParams&, const ContactLawParams&) = default;
};

/// Validates p and builds the law (dim = 2 or 3).
template <int dim> ContactLaw<dim> make_contact_law(const ContactLawParams& p);

extern template ContactLaw<2> make_contact_law<2>(const ContactLawParams&);
extern template ContactLaw<3> make_contact_law<3>(const ContactLawParams&);

} // namespace granpack
