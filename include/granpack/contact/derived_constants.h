#pragma once
// Constants derived from the contact law's parameters and from a packing's scales, each
// written once, beside the law they belong to: the engine, the stages, analysis, stiffness
// and bench call these instead of spelling the formulas again (docs/contact-law.md).
// The formulas of the law itself (K_N(h), N^e, α, K_T, Walton, Coulomb) are in the sub-model
// headers, shared by ContactLaw and the batched kernel.
#include <algorithm>
#include <cmath>

namespace granpack {

/// Ẽ = E/(1 − ν²), the modulus of the Hertz law in [AR]'s form N^e = (2/3) Ẽ √R* h^{3/2}
/// ([AR] eq. 1 for equal spheres: N = Ẽ √a h^{3/2}/3; Johnson's E* = Ẽ/2).
inline double e_tilde_of(double young_modulus, double poisson_ratio) {
  return young_modulus / (1.0 - poisson_ratio * poisson_ratio);
}

/// κ = (Ẽ/P)^{2/3}, the stiffness number of a Hertz packing under pressure P ([AR] eq. 21):
/// the inverse of the typical overlap h/a. (The 2D analysis passes Ẽ a: P is a force per
/// length there; docs/analysis-statistics.md.)
inline double hertz_stiffness_number(double e_tilde, double pressure) {
  return std::pow(e_tilde / pressure, 2.0 / 3.0);
}

/// κ of a Hertz packing of grains of diameter a under pressure P in `dim` dimensions:
/// (Ẽ a² / (P a^(dim−1)))^{2/3}, i.e. (Ẽ/P)^{2/3} in 3D ([AR] eq. 21) and (Ẽ a/P)^{2/3} in 2D,
/// where P is a force per length (grain_section below).
inline double hertz_stiffness_number(double e_tilde, double a, int dim, double pressure) {
  return hertz_stiffness_number(dim == 3 ? e_tilde : e_tilde * a, pressure);
}

/// [GRC]'s κ of a cohesive Hertz contact: (Ẽ a²/F0)^{2/3}, the same number with the cohesion F0
/// as the force scale instead of P a^(dim−1) (sec. II C; the linear law's is a K_N/F0).
inline double hertz_cohesive_stiffness_number(double e_tilde, double a, double f0) {
  return std::pow(e_tilde * a * a / f0, 2.0 / 3.0);
}

/// R* = R_i R_j/(R_i + R_j) of two equal grains of diameter a: a/4 ([AR] eq. 1-2).
inline double equal_grains_effective_radius(double a) {
  return 0.25 * a;
}

/// m* = m_i m_j/(m_i + m_j) of two grains of equal mass m: m/2.
inline double equal_grains_effective_mass(double m) {
  return 0.5 * m;
}

/// a^(dim−1): the area (3D) or length (2D, forces per unit thickness) over which a pressure
/// acts on one grain of diameter a, so that P a^(dim−1) is a force and F/a^(dim−1) a pressure.
inline double grain_section(int dim, double a) {
  return dim == 3 ? a * a : a;
}

/// P a^(dim−1): the force scale of a packing under pressure P, [AR]'s a²P (sec. III) and
/// [GRC]'s P a in 2D.
inline double pressure_force(int dim, double a, double pressure) {
  return grain_section(dim, a) * pressure;
}

/// [GRC] II D's force scale F1 = max(F0, P a^(dim−1)). Without cohesion (F0 = 0) it is
/// P a^(dim−1) itself, [AR]'s a²P, whatever the sign of P. With cohesion F1 >= F0 > 0: at
/// P* = 0 a scale from P alone would be zero or negative (the equilibrium criteria, the
/// force-carrying threshold and the "vanishing force" tolerance are all multiples of F1).
inline double force_scale_f1(int dim, double a, double pressure, double cohesion_force) {
  const double pf = pressure_force(dim, a, pressure);
  return cohesion_force > 0 ? std::max(cohesion_force, pf) : pf;
}

/// [GRC]'s velocity scale of cohesion V* = sqrt(F0 D0 / m) for grains of mass m: the
/// escape velocity of a pair is V* with m* for m (eq. 7; Cohesion::escape_velocity).
inline double cohesive_velocity_scale(double f0, double d0, double mass) {
  return std::sqrt(f0 * d0 / mass);
}

/// [GRC]'s time scale of cohesion T0 = sqrt(m a / F0) for grains of mass m, diameter a.
inline double cohesive_time_scale(double f0, double a, double mass) {
  return std::sqrt(mass * a / f0);
}

/// [AR]'s force-carrying threshold, a fraction of F1 (force_scale_f1): contacts with N^e above
/// it carry force (the equilibrium tolerance, below which forces are not resolved); the default
/// of `granpack analyze` and `stiffness`, and the rattler flags of the files' /network.
inline constexpr double kCarryingThreshold = 1e-4;

/// Fewest force-carrying contacts with non-rattlers that keep a grain in the backbone, the
/// iterative rattler rule of [AR] sec. III B: without friction the contact forces are normal
/// and hold a grain only with dim + 1 contacts (normals not all in one half-space); with
/// friction two contacts can (equal and opposite forces along the line between them).
inline int min_backbone_contacts(int dim, double friction) {
  return friction > 0 ? 2 : dim + 1;
}

} // namespace granpack
