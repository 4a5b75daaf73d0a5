#pragma once
// What the batched contact kernels of both dimensions (dynamics/hertz_mindlin_batch in 3D,
// dynamics/disk_contact_batch in 2D) share: the constants of the normal elasticity, normal
// damping, tangential stiffness and friction they evaluate, and the form in which the kernels
// use them (uniform choices turned into arithmetic, so that the loop bodies have no control
// flow). MPI-free.
#include <cstddef>
#include <optional>
#include <variant>

#include "granpack/contact/contact_law.h"
#include "granpack/contact/normal_elasticity.h"
#include "granpack/core/error.h"

namespace granpack {

/// The constants of a law's normal, damping, tangential and friction parts.
struct BatchLawConstants {
  double e_tilde = 0;    ///< Hertz Ẽ (linear_k_n = 0) ...
  double linear_k_n = 0; ///< ... or a linear spring K_N (e_tilde = 0)
  double zeta = 0;       ///< damping fraction ζ
  bool tension = true;   ///< N^e + N^v may pull (NormalDamping::tension)
  double k_t_ratio = 0;  ///< K_T / K_N
  bool walton = true;    ///< Walton rescaling of T when N^e decreases
  double mu = 0;         ///< Coulomb coefficient (may be +inf)

  /// Those of `law`, or nullopt if its K_T is not proportional to K_N (the batch kernels
  /// handle only that case; the other laws go to the scalar loop).
  template <int dim> static std::optional<BatchLawConstants> of(const ContactLaw<dim>& law) {
    if (!law.tangential.proportional_to_normal())
      return std::nullopt;
    BatchLawConstants c;
    if (const auto* hz = std::get_if<HertzNormal>(&law.normal))
      c.e_tilde = hz->e_tilde;
    else
      c.linear_k_n = std::get<LinearNormal>(law.normal).k_n;
    c.zeta = law.damping.zeta;
    c.tension = law.damping.tension;
    c.k_t_ratio = law.tangential.value;
    c.walton = law.tangential.walton_rescaling;
    c.mu = law.friction.mu;
    return c;
  }
};

/// BatchLawConstants as the kernels use them: K_N = Ẽ sqrt(R* h) + K_lin (one of the two is
/// zero), N^e = (2/3 or 1) K_N h; ζ = 0 gives a zero damping coefficient; μ = +inf never
/// slides (t2 > inf is false); the linear law's stiffness ratio is 1, so Walton's rescaling
/// applies to Hertz only.
struct BatchLawTerms {
  bool hertz;
  double e_tilde, k_lin, n_factor, two_zeta;
  bool tension;
  double k_t_ratio, mu;
  bool walton;

  explicit BatchLawTerms(const BatchLawConstants& c)
      : hertz(c.e_tilde > 0), e_tilde(c.e_tilde), k_lin(hertz ? 0.0 : c.linear_k_n),
        n_factor(hertz ? kHertzForceFactor : kLinearForceFactor), two_zeta(2.0 * c.zeta),
        tension(c.tension), k_t_ratio(c.k_t_ratio), mu(c.mu), walton(c.walton && hertz) {}
};

/// What a batch kernel sums over the lanes it evaluates (those not flagged `exact`).
template <int dim> struct BatchSums {
  double virial[dim * dim] = {};         ///< sum of F ⊗ r (row-major: F_a r_b at [dim a + b])
  double virial_elastic[dim * dim] = {}; ///< the same with the static force (N^e + N^a) n + T
  double max_overlap = 0;                ///< largest h / min(R_i, R_j)
  long contacts = 0;                     ///< lanes evaluated (contacts, distant interactions)

  BatchSums& operator+=(const BatchSums& o) {
    for (int k = 0; k < dim * dim; ++k) {
      virial[k] += o.virial[k];
      virial_elastic[k] += o.virial_elastic[k];
    }
    max_overlap = max_overlap < o.max_overlap ? o.max_overlap : max_overlap; // as std::max
    contacts += o.contacts;
    return *this;
  }
};

/// The frame of every batch kernel's entry point: lanes [0, n) of `b` padded to whole vectors
/// of 8 (every lane then goes through the same instructions; Batch::pad_lane fills the rest),
/// evaluated by `lanes(padded, s)` into fresh sums s, which are then added to `sums`.
template <class Batch, int dim, class Lanes>
void evaluate_padded(Batch& b, std::size_t n, BatchSums<dim>& sums, Lanes&& lanes) {
  const std::size_t padded = (n + 7) / 8 * 8;
  GRANPACK_ASSERT(padded <= Batch::kCapacity, "batch overflow");
  for (std::size_t l = n; l < padded; ++l)
    b.pad_lane(l);
  BatchSums<dim> s;
  lanes(padded, s);
  sums += s;
}

} // namespace granpack
