#pragma once
// Closed forms for binary collisions, used by the engine to choose time steps and by tests.
// Conventions of docs/contact-law.md: Ẽ = E/(1-ν²), E* = Ẽ/2 (Hertz: N = (4/3) E* sqrt(R*)
// h^{3/2}).

namespace granpack {

/// ∫_0^1 (1 - x^{5/2})^{-1/2} dx · 2 = 2.94328...: the Hertz duration constant.
double hertz_duration_constant();

/// Duration of an undamped head-on Hertz collision at approach velocity v:
/// τ = 2.9432 (15 m* / (16 E* sqrt(R*)))^{2/5} v^{-1/5}.
double hertz_contact_duration(double e_tilde, double r_eff, double m_eff, double v);

/// Maximum overlap of that collision: (15 m* v² / (16 E* sqrt(R*)))^{2/5}.
double hertz_max_overlap(double e_tilde, double r_eff, double m_eff, double v);

/// Half period of the linear spring K with reduced mass m*: π sqrt(m*/K) (contact duration).
double linear_contact_duration(double k, double m_eff);

/// Contact duration with damping ratio ζ (N^v = 2ζ sqrt(m* K) ḣ): π / (ω0 sqrt(1 - ζ²)).
double damped_linear_contact_duration(double k, double m_eff, double zeta);

/// Restitution of the damped linear oscillator: exp(-ζπ / sqrt(1 - ζ²)).
double linear_restitution(double zeta);

/// Stability limit of velocity Verlet for one linear spring: 2 sqrt(m*/K) = (2/π) duration.
double linear_critical_time_step(double k, double m_eff);

} // namespace granpack
