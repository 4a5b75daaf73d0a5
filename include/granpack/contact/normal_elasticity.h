#pragma once
// Normal elasticity sub-models: Hertz ([AR] eq. 1-2, effective-radius form) and linear
// ([GRC] eq. 4). Each is a tiny value type; NormalElasticity is the closed set of choices.
// Convention: h > 0 is an overlap, N > 0 is repulsive.
#include <cmath>
#include <variant>

namespace granpack {

/// Value and slope of an elastic normal law at one deflection.
struct NormalResponse {
  double force = 0;      ///< elastic normal force N^e (repulsive > 0)
  double stiffness = 0;  ///< K_N = dN^e/dh
};

/// (1 + x)^{1/3} by its binomial series to x⁵, for |x| < 1e-3 (truncation < 0.03 x⁶ < 3e-20).
/// Shared by HertzNormal::stiffness_ratio and the batched contact kernel.
inline double cbrt_one_plus_series(double x) {
  return 1.0 + x * (1.0 / 3.0 - x * (1.0 / 9.0 - x * (5.0 / 81.0 - x * (10.0 / 243.0 - x * (22.0 / 729.0)))));
}

/// Hertz: N = (2/3) Ẽ sqrt(R*) h^{3/2}, K_N = Ẽ sqrt(R* h), Ẽ = E/(1-ν²).
/// For equal spheres of diameter a (R* = a/4): N = Ẽ sqrt(a) h^{3/2}/3 ([AR] eq. 1).
struct HertzNormal {
  double e_tilde = 0;  ///< Ẽ = E / (1 - ν²)

  NormalResponse response(double h, double r_eff) const {
    if (!(h > 0)) return {};
    const double k = e_tilde * std::sqrt(r_eff * h);
    return {(2.0 / 3.0) * k * h, k};
  }
  /// K_N(N_new) / K_N(N_old) at fixed R*: (N_new/N_old)^{1/3} ([AR] eq. 2).
  double stiffness_ratio(double n_new, double n_old) const {
    if (!(n_new > 0)) return 0.0;
    // From one step to the next N changes by ~1e-6..1e-3 relative: there (1 + x)^{1/3} is
    // its binomial series to x⁵ (truncation < 0.03 x⁶ < 3e-20), cheaper than std::cbrt.
    const double x = n_new / n_old - 1.0;
    if (std::abs(x) < 1e-3) return cbrt_one_plus_series(x);
    return std::cbrt(n_new / n_old);
  }
};

/// Linear spring: N = K_N h with constant K_N.
struct LinearNormal {
  double k_n = 0;

  NormalResponse response(double h, double /*r_eff*/) const {
    if (!(h > 0)) return {};
    return {k_n * h, k_n};
  }
  double stiffness_ratio(double /*n_new*/, double /*n_old*/) const { return 1.0; }
};

using NormalElasticity = std::variant<HertzNormal, LinearNormal>;

/// N^e(h) and K_N(h) of whichever law is held (zero when h <= 0).
inline NormalResponse normal_response(const NormalElasticity& law, double h, double r_eff) {
  if (const auto* hz = std::get_if<HertzNormal>(&law)) return hz->response(h, r_eff);
  return std::get<LinearNormal>(law).response(h, r_eff);
}

/// K_N at elastic force n_new over K_N at n_old (n_old > 0), for the Walton rescaling.
inline double normal_stiffness_ratio(const NormalElasticity& law, double n_new, double n_old) {
  if (const auto* hz = std::get_if<HertzNormal>(&law)) return hz->stiffness_ratio(n_new, n_old);
  return std::get<LinearNormal>(law).stiffness_ratio(n_new, n_old);
}

}  // namespace granpack
