#pragma once
// Normal elasticity sub-models: Hertz ([AR] eq. 1-2, effective-radius form) and linear
// ([GRC] eq. 4). Each is a tiny value type; NormalElasticity is the closed set of choices.
// Convention: h > 0 is an overlap, N > 0 is repulsive.
#include <cmath>
#include <variant>

namespace granpack {

/// Value and slope of an elastic normal law at one deflection.
struct NormalResponse {
  double force = 0;     ///< elastic normal force N^e (repulsive > 0)
  double stiffness = 0; ///< K_N = dN^e/dh
};

/// (1 + x)^{1/3} by its binomial series to x⁵, for |x| < 1e-3 (truncation < 0.03 x⁶ < 3e-20).
/// Shared by HertzNormal::stiffness_ratio and the batched contact kernel.
inline double cbrt_one_plus_series(double x) {
  return 1.0 + x * (1.0 / 3.0 -
                    x * (1.0 / 9.0 - x * (5.0 / 81.0 - x * (10.0 / 243.0 - x * (22.0 / 729.0)))));
}

// The formulas of the normal laws, one inline function each: HertzNormal and LinearNormal
// below and the batched kernel (dynamics/hertz_mindlin_batch) both call them, so the law is
// written once. h > 0 is assumed (callers test it, or select the result away).

/// Hertz K_N = dN^e/dh = Ẽ sqrt(R* h) ([AR] eq. 2 in effective-radius form).
inline double hertz_stiffness(double e_tilde, double r_eff, double h) {
  return e_tilde * std::sqrt(r_eff * h);
}

/// N^e = c K_N h: c = 2/3 for Hertz (N^e ∝ h^{3/2}, [AR] eq. 1), 1 for the linear spring.
inline constexpr double kHertzForceFactor = 2.0 / 3.0;
inline constexpr double kLinearForceFactor = 1.0;
inline double normal_elastic_force(double factor, double k_n, double h) {
  return factor * k_n * h;
}

/// Relative change of N^e below which K_N(N_new)/K_N(N_old) = (1 + x)^{1/3} is its series
/// (cbrt_one_plus_series): from one step to the next N^e changes by ~1e-6..1e-3.
inline constexpr double kSmallLoadChange = 1e-3;

/// x = N_new/N_old - 1, the relative change of the elastic normal force (Walton rescaling).
inline double relative_load_change(double n_new, double n_old) {
  return n_new / n_old - 1.0;
}

/// Hertz overlap at which N^e = force: h = (3 N / (2 Ẽ sqrt(R*)))^{2/3} (eq. 1 inverted).
inline double hertz_overlap_at_force(double e_tilde, double r_eff, double force) {
  return std::pow(1.5 * force / (e_tilde * std::sqrt(r_eff)), 2.0 / 3.0);
}

/// K_N of a Hertz contact carrying the force N^e = force: the stiffness a time step is
/// chosen from (stages, bench).
inline double hertz_stiffness_at_force(double e_tilde, double r_eff, double force) {
  return hertz_stiffness(e_tilde, r_eff, hertz_overlap_at_force(e_tilde, r_eff, force));
}

/// Hertz: N = (2/3) Ẽ sqrt(R*) h^{3/2}, K_N = Ẽ sqrt(R* h), Ẽ = E/(1-ν²) (e_tilde_of).
/// For equal spheres of diameter a (R* = a/4): N = Ẽ sqrt(a) h^{3/2}/3 ([AR] eq. 1).
struct HertzNormal {
  double e_tilde = 0; ///< Ẽ = E / (1 - ν²)

  NormalResponse response(double h, double r_eff) const {
    if (!(h > 0))
      return {};
    const double k = hertz_stiffness(e_tilde, r_eff, h);
    return {normal_elastic_force(kHertzForceFactor, k, h), k};
  }
  /// K_N(N_new) / K_N(N_old) at fixed R*: (N_new/N_old)^{1/3} ([AR] eq. 2).
  double stiffness_ratio(double n_new, double n_old) const {
    if (!(n_new > 0))
      return 0.0;
    // Near 1, (1 + x)^{1/3} by its binomial series, cheaper than std::cbrt.
    const double x = relative_load_change(n_new, n_old);
    if (std::abs(x) < kSmallLoadChange)
      return cbrt_one_plus_series(x);
    return std::cbrt(n_new / n_old);
  }
};

/// Linear spring: N = K_N h with constant K_N.
struct LinearNormal {
  double k_n = 0;

  NormalResponse response(double h, double /*r_eff*/) const {
    if (!(h > 0))
      return {};
    return {normal_elastic_force(kLinearForceFactor, k_n, h), k_n};
  }
  double stiffness_ratio(double /*n_new*/, double /*n_old*/) const { return 1.0; }
};

using NormalElasticity = std::variant<HertzNormal, LinearNormal>;

/// N^e(h) and K_N(h) of whichever law is held (zero when h <= 0).
inline NormalResponse normal_response(const NormalElasticity& law, double h, double r_eff) {
  if (const auto* hz = std::get_if<HertzNormal>(&law))
    return hz->response(h, r_eff);
  return std::get<LinearNormal>(law).response(h, r_eff);
}

/// K_N at elastic force n_new over K_N at n_old (n_old > 0), for the Walton rescaling.
inline double normal_stiffness_ratio(const NormalElasticity& law, double n_new, double n_old) {
  if (const auto* hz = std::get_if<HertzNormal>(&law))
    return hz->stiffness_ratio(n_new, n_old);
  return std::get<LinearNormal>(law).stiffness_ratio(n_new, n_old);
}

} // namespace granpack
