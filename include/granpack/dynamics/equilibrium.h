#pragma once
// The equilibrium criteria of [AR] sec. III and [GRC] II D: a stage ends when all of
//   max_i |F_i^el|                < force   * F1
//   max_i |Gamma_i^el|            < moment  * F1 a      (off unless set: [AR] has none)
//   max_a |sigma_aa^el - Sigma_a| < stress  * F1 / a^(dim-1)
//   E_kin / n                     < kinetic * F1 a
// hold, F^el, Gamma^el and sigma^el being the static contact forces, moments and stresses
// (elastic plus cohesive attraction; the viscous part is excluded, as in the papers: at the
// kinetic threshold viscous forces can still exceed the force threshold by two orders of
// magnitude). F1 = max(F0, P a^(dim-1)) is [GRC]'s force scale; without cohesion it is
// [AR]'s a^2 P (3D), and the scales are a^2 P, P and P a^3.
// The kinetic energy counts every grain, translation and spin, as both papers do.
#include <limits>

#include "granpack/contact/derived_constants.h"

namespace granpack {

struct EquilibriumTolerances {
  double force = 1e-4;   ///< max net static force on a grain / force scale
  double stress = 1e-4;  ///< max |sigma_aa - Sigma_a| / stress scale
  double kinetic = 1e-8; ///< kinetic energy per grain / energy scale
  double moment = std::numeric_limits<double>::infinity(); ///< max net static moment / moment scale
  bool checks_moment() const { return moment < std::numeric_limits<double>::infinity(); }
  friend bool operator==(const EquilibriumTolerances&, const EquilibriumTolerances&) = default;
};

/// The scales the criteria are normalised by.
struct EquilibriumScales {
  double force = 1, stress = 1, energy = 1, moment = 1;
  /// F1 = max(F0, P a^(dim-1)): force F1, stress F1/a^(dim-1), energy and moment F1 a.
  static EquilibriumScales of(int dim, double a, double pressure, double cohesion_force) {
    const double f1 = force_scale_f1(dim, a, pressure, cohesion_force);
    return {f1, f1 / grain_section(dim, a), f1 * a, f1 * a};
  }
};

/// Measured values, already normalised by the scales.
struct EquilibriumMeasure {
  double force = 0, stress = 0, kinetic = 0, moment = 0;
  bool satisfies(const EquilibriumTolerances& t) const {
    return static_state(t) && kinetic < t.kinetic;
  }
  /// The force, moment and stress criteria hold (the packing is static but may still move).
  bool static_state(const EquilibriumTolerances& t) const {
    return force < t.force && stress < t.stress && moment < t.moment;
  }
};

} // namespace granpack
