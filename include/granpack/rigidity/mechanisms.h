#pragma once
// Mechanisms of the backbone ([AR] sec. II C 2, IV D, App. E): the null space of K(1) (that
// of G). Known ones are removed explicitly, so that what is left is a positive-definite
// matrix whose factorisation counts whatever else there is:
//   - the dim trivial translations: one non-divalent grain's translations are pinned
//     (rows and columns replaced by <k_n> on the diagonal); every null vector restricted to
//     that grain is a translation, so pinning removes exactly dim dimensions;
//   - one free rolling per divalent grain (3D, friction): its exact rolling vector v is
//     checked to be null (K(1) v = 0) and stiffened by <k_n> v vᵀ, as [AR] attribute "some
//     energy cost" to these motions; as G v = 0 the border K_eu v = 0 and the response to
//     strains is unchanged;
//   - with rolling resistance in 3D, one free pivoting per part of the network hanging from a
//     single contact (analysis/pivoting_clusters.h; a grain with one contact is the smallest),
//     checked the same way and stiffened by a pivoting spring on that contact; there the
//     divalent modes are not null (they roll on both contacts) and are not removed.
// MUMPS then reports the null pivots (unexpected mechanisms) and the inertia of the grain
// block; SLEPc gives its smallest eigenvalues by shift-and-invert at 0 on the same factors;
// the strain mechanisms are the null space of the Schur complement (condensation.h).
#include <vector>

#include "granpack/rigidity/direct_solver.h"
#include "granpack/rigidity/stiffness_system.h"

namespace granpack {

struct DivalentGrain {
  GlobalId grain = 0;
  GlobalId neighbours[2] = {0, 0};
};

struct KnownMechanisms {
  std::vector<DivalentGrain> divalent;
  double divalent_residual = 0; ///< |K(1) V| / (<k_n> |V|), V the sum of the rolling modes
  /// Parts hanging from one contact that pivot freely (3D, rolling resistance): the hinge
  /// grain, then (neighbour across the hinge, number of grains in the part).
  std::vector<DivalentGrain> pivoting;
  double pivoting_residual = 0; ///< the same for the pivoting modes
  GlobalId pinned_grain = -1;
};

/// Checks and stiffens the divalent rolling and pivoting modes and pins one grain, in both
/// K(1) and K.
/// Collective.
template <int dim> KnownMechanisms remove_known_mechanisms(StiffnessSystem<dim>& s);

/// The `count` smallest eigenvalues of the factorised symmetric grain block `a`, divided by
/// <k_n> (SLEPc, Krylov-Schur on the inverse: shift-and-invert at 0 with `solver`'s factors).
std::vector<double> smallest_eigenvalues(Mat a, const DirectSolver& solver, int count, double scale,
                                         double* seconds);

/// The `count` softest modes of the factorised symmetric grain block `a` (the eigenpairs
/// nearest 0 of smallest_eigenvalues()), for `granpack stiffness --modes`: eigenvalues / scale
/// on every rank; on rank 0 each mode's entries per backbone grain (grain_dofs each, in the
/// order of numbering.ids), unit norm; empty elsewhere. Collective.
struct SoftModes {
  std::vector<double> eigenvalues;
  std::vector<std::vector<double>> values;
};
SoftModes softest_modes(Mat a, const DirectSolver& solver, const GrainNumbering& numbering,
                        int grain_dofs, int count, double scale);

/// Unexpected mechanisms, counted and named: the eigenvectors of the (singular) stiffened
/// K(1)_uu with eigenvalue below `tolerance` <k_n>, from SLEPc on the inverse of
/// K(1)_uu + shift <k_n> 1 (a second, regularised factorisation), asking for `count`, then
/// twice as many, until one eigenvalue is above the tolerance. MUMPS's null-pivot count
/// only triggers this: on a matrix with many null directions it depends on the pivot order
/// (98 on one rank, 90 on two for the same floppy network, whose nullity is larger). Each
/// mode lists the ids of the grains carrying at least 10 % of its largest per-grain amplitude
/// (at most 50, largest first). Collective.
std::vector<std::vector<GlobalId>> floppy_modes(Mat a, const GrainNumbering& numbering,
                                                int grain_dofs, double mean_kn, int count,
                                                double shift, double tolerance);

} // namespace granpack
