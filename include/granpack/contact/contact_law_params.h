#pragma once
// Plain parameters of a contact law, as a deck fills them, and the factory that validates
// them and builds ContactLaw<dim>. Bad values throw InputError; cohesion or rolling
// resistance (non-zero F0, K_r, μ_r) throw NotImplemented for now.
#include <limits>

#include "granpack/contact/contact_law.h"

namespace granpack {

enum class NormalLawKind { kHertz, kLinear };

struct ContactLawParams {
  NormalLawKind normal = NormalLawKind::kHertz;
  double young_modulus = 0;  ///< E (Hertz)
  double poisson_ratio = 0;  ///< ν (Hertz; also kMindlin tangential)
  double k_n = 0;            ///< linear normal stiffness K_N
  TangentialStiffnessKind tangential = TangentialStiffnessKind::kMindlin;
  double k_t = 0;            ///< kConstant: K_T
  double k_t_ratio = 0;      ///< kRatio: K_T / K_N
  double damping_ratio = 0;  ///< ζ in [0, 1)
  double friction = 0;       ///< μ in [0, +inf]
  bool walton_rescaling = true;
  // Future parts ([GRC]); must stay 0 until implemented.
  double cohesion_force = 0, cohesion_range = 0;  ///< F0, D0
  double rolling_stiffness = 0, rolling_friction = 0;  ///< K_r, μ_r
};

/// Validates p and builds the law (dim = 2 or 3).
template <int dim> ContactLaw<dim> make_contact_law(const ContactLawParams& p);

extern template ContactLaw<2> make_contact_law<2>(const ContactLawParams&);
extern template ContactLaw<3> make_contact_law<3>(const ContactLawParams&);

}  // namespace granpack
