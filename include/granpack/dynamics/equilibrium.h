#pragma once
// The equilibrium criteria of [AR] sec. III: a stage ends when all of
//   max_i |F_i^el|                < force   * a^2 P
//   max_a |sigma_aa^el - Sigma_a| < stress  * P
//   E_kin / n                     < kinetic * P a^3
// hold, F^el and sigma^el being the elastic contact forces and stresses (the viscous part is
// excluded, as in the paper: at the kinetic threshold viscous forces can still exceed the
// force threshold by two orders of magnitude). [GRC] II D uses the same form with the force
// scale F1 = max(F0, Pa) instead of a^2 P; the caller supplies the scales.
// The kinetic energy leaves out the spin of grains that touch nothing (a caged rattler
// spinning freely never loses that energy, and it has no mechanical effect).
namespace granpack {

struct EquilibriumTolerances {
  double force = 1e-4;    ///< max net elastic force on a grain / force scale
  double stress = 1e-4;   ///< max |sigma_aa - Sigma_a| / stress scale
  double kinetic = 1e-8;  ///< kinetic energy per grain / energy scale
  friend bool operator==(const EquilibriumTolerances&, const EquilibriumTolerances&) = default;
};

/// Measured values, already normalised by the scales.
struct EquilibriumMeasure {
  double force = 0, stress = 0, kinetic = 0;
  bool satisfies(const EquilibriumTolerances& t) const {
    return force < t.force && stress < t.stress && kinetic < t.kinetic;
  }
  /// The force and stress criteria hold (the packing is static but may still move).
  bool static_state(const EquilibriumTolerances& t) const {
    return force < t.force && stress < t.stress;
  }
};

}  // namespace granpack
