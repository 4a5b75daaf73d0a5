#pragma once
// The 2D contact law of [GRC] (linear or Hertz normal force, normal damping, K_T ∝ K_N,
// Coulomb friction, and optionally the cohesion F0, D0 with its distant interactions and the
// rolling resistance K_r, μ_r, ζ_r) evaluated on a batch of contacts at once, in structure of
// arrays, so that the compiler evaluates 4 or 8 contacts per instruction: the 2D counterpart
// of dynamics/hertz_mindlin_batch (docs/performance.md).
//
// It computes what ContactLaw<2>::force computes (same formulas, called from the same inline
// functions of contact/*.h; the results differ only by rounding: one reciprocal for several
// divisions, fused multiply-adds) on the path of an MD run: a touching pair whose contact turns
// by less than 1e-3 rad in the step and, for Hertz with Walton's rescaling, whose N^e drops by
// less than 0.1 %, or a cohesive pair across a gap shorter than D0. A pair off that path (a
// fast first touch, a pair out of range by rounding) is flagged `exact` and the caller
// evaluates it with ContactLaw<2>::force from its untouched history. MPI-free.
#include <cstddef>
#include <optional>

#include "granpack/contact/contact_law.h"
#include "granpack/dynamics/batch_law.h"

namespace granpack {

/// The constants of a 2D law the batch kernel needs: those of BatchLawConstants, the
/// cohesion and the rolling resistance.
struct DiskContactConstants : BatchLawConstants {
  double f0 = 0, d0 = 0;                ///< cohesion F0, D0 (both 0: none)
  bool rolling = false;                 ///< rolling resistance (K_r > 0)
  double k_r = 0, mu_r = 0, zeta_r = 0; ///< K_r, μ_r (may be +inf), ζ_r

  /// The constants of `law` if the batch can evaluate it (K_T proportional to K_N: the other
  /// laws go to the scalar loop).
  static std::optional<DiskContactConstants> of(const ContactLaw<2>& law);
};

/// One batch of pairs: inputs gathered by the caller, outputs written by evaluate().
/// Field arrays are 64-byte aligned; evaluate() pads the lanes past the count itself.
struct alignas(64) DiskContactBatch {
  static constexpr std::size_t kCapacity = 128; ///< a multiple of every SIMD width
  template <class T> using Lane = T[kCapacity];

  // Inputs. r = r_ij (i -> j); v = v_j - v_i including the cell's affine velocity; ω about z.
  Lane<double> rx, ry, rad_i, rad_j, mass_i, mass_j;
  Lane<double> vx, vy, wi, wj;
  // The stored history, updated in place: T, N^e, rolling rotation δθ.
  Lane<double> tx, ty, n_old, rolling;
  // Outputs.
  Lane<double> fx, fy; ///< force on j: N n + T (N = N^e + N^v + N^a), or N^a n across a gap
  Lane<double> ti, tj; ///< torques on i and j, rolling moments included
  Lane<int> flags;     ///< ContactFlag bits of the new state (kSliding, kRollingPlastic, kDistant)
  Lane<int> exact;     ///< 1: off the batch's path, use ContactLaw::force

  /// Makes lane l a padding lane: a copy of lane 0's geometry, at rest, with no history.
  void pad_lane(std::size_t l) {
    rx[l] = rx[0], ry[l] = ry[0];
    rad_i[l] = rad_i[0], rad_j[l] = rad_j[0];
    mass_i[l] = mass_i[0], mass_j[l] = mass_j[0];
    vx[l] = vy[l] = wi[l] = wj[l] = 0;
    tx[l] = ty[l] = n_old[l] = rolling[l] = 0;
  }
};

using DiskContactSums = BatchSums<2>;

/// Evaluates lanes [0, n) over a time step dt (padding them to a multiple of 8 internally)
/// and adds their virials, largest overlap and count to `sums`.
void evaluate(const DiskContactConstants& c, DiskContactBatch& b, std::size_t n, double dt,
              DiskContactSums& sums);

} // namespace granpack
