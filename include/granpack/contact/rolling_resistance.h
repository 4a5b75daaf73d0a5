#pragma once
// Slot for [GRC]'s rolling resistance (eq. 9-10): elastic relative rolling rotation stored in
// ContactState::rolling with stiffness K_r, moment bounded by μ_r N^e (kRollingPlastic);
// in 3D on the rolling components only, pivoting left free. NOT IMPLEMENTED YET: the factory
// refuses it (NotImplemented) and ContactLaw::force marks where it plugs in.

namespace granpack {

struct RollingResistance {
  double k_r = 0;   ///< rolling stiffness K_r (moment per radian)
  double mu_r = 0;  ///< rolling friction μ_r (a length): |Γ^r| <= μ_r N^e
};

}  // namespace granpack
