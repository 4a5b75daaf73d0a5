#pragma once
// The contact law of [AR] (3D Hertz-Mindlin, Walton rescaling, Coulomb, normal damping; no
// cohesion, no rolling resistance) evaluated on a batch of contacts at once, in structure of
// arrays, so that the compiler evaluates 4 or 8 contacts per instruction (docs/performance.md).
//
// It computes exactly what ContactLaw<3>::force computes (same formulas, same order of
// operations; the results differ only by rounding, e.g. fused multiply-adds), on the path every
// contact of a dense MD run takes: touching pair, small rotation of the contact over the step
// (x² < 1e-6) and small relative change of N^e when it decreases (|x| < 1e-3). A contact off
// that path (first touch of a fast collision, a pair that does not actually overlap) is
// flagged `exact` and the caller evaluates it with ContactLaw<3>::force instead, so the batch
// never approximates anything the scalar law would not.
//
// Nothing here allocates or branches per contact; the caller gathers the pairs' data into
// the batch, calls evaluate() and scatters the results. MPI-free.
#include <cstddef>
#include <optional>

#include "granpack/contact/contact_law.h"
#include "granpack/dynamics/batch_law.h"

namespace granpack {

/// The constants of the law the batch kernel needs, taken from a ContactLaw<3>.
struct HertzMindlinConstants : BatchLawConstants {
  /// The constants of `law` if the batch kernel can evaluate it: no cohesion, no rolling
  /// resistance, K_T proportional to K_N. Otherwise nullopt (the caller uses the scalar law).
  static std::optional<HertzMindlinConstants> of(const ContactLaw<3>& law);
};

/// One batch of contacts: inputs gathered by the caller, outputs written by evaluate().
/// Field arrays are 64-byte aligned; evaluate() pads the lanes past the count itself.
struct alignas(64) HertzMindlinBatch {
  static constexpr std::size_t kCapacity = 128; ///< a multiple of every SIMD width
  // kCapacity doubles (or ints) are a multiple of 64 bytes: every array starts aligned.
  template <class T> using Lane = T[kCapacity];

  // Inputs. r = r_ij (i -> j, m); v = v_j - v_i including the cell's affine velocity.
  Lane<double> rx, ry, rz, rad_i, rad_j, mass_i, mass_j;
  Lane<double> vx, vy, vz, wix, wiy, wiz, wjx, wjy, wjz;
  Lane<double> tx, ty, tz; ///< stored T (updated in place to the new T)
  Lane<double> n_old;      ///< stored N^e (updated in place to the new N^e)
  // Outputs.
  Lane<double> fx, fy, fz;                   ///< N n + T on j (total normal force: N^e + N^v)
  Lane<double> tix, tiy, tiz, tjx, tjy, tjz; ///< torques on i and j
  Lane<double> overlap;                      ///< h
  Lane<int> sliding;                         ///< 1: T on the Coulomb cone
  Lane<int> exact;                           ///< 1: off the batch's path, use ContactLaw::force

  /// Makes lane l a padding lane: a copy of lane 0's geometry, at rest, with no history.
  void pad_lane(std::size_t l) {
    rx[l] = rx[0], ry[l] = ry[0], rz[l] = rz[0];
    rad_i[l] = rad_i[0], rad_j[l] = rad_j[0];
    mass_i[l] = mass_i[0], mass_j[l] = mass_j[0];
    vx[l] = vy[l] = vz[l] = 0;
    wix[l] = wiy[l] = wiz[l] = wjx[l] = wjy[l] = wjz[l] = 0;
    tx[l] = ty[l] = tz[l] = 0;
    n_old[l] = 0;
  }
};

using HertzMindlinSums = BatchSums<3>;

/// Evaluates lanes [0, n) over a time step dt (padding them to a multiple of 8 internally)
/// and adds their virials, largest overlap and count to `sums`.
void evaluate(const HertzMindlinConstants& c, HertzMindlinBatch& b, std::size_t n, double dt,
              HertzMindlinSums& sums);

} // namespace granpack
