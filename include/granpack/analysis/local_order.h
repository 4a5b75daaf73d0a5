#pragma once
// Local bond-orientational order per grain, for /network (docs/hdf5-schema.md): in 3D
// Steinhardt's Q6 of the grain's bonds ([AR] eq. 31, analysis/bond_order), in 2D the hexatic
// |psi6| = |(1/N_b) sum_j exp(6 i theta_ij)|. A bond joins two centres closer than d_c. The
// crystalline flag that goes with it: in 3D [AR]'s rule (eq. 34: at least 7 bonds whose
// normalised q6 agree to 0.5, as `granpack analyze` counts x_cr; the exchange of q6 between
// ranks is engine/network_fields'), in 2D |psi6| >= kCrystallinePsi6. MPI-free.
#include <span>
#include <vector>

#include "granpack/core/cell.h"
#include "granpack/core/particles.h"

namespace granpack {

/// d_c / a: [AR] table II's 1.40 a (near the first minimum of g(r)), the d_c of the summary
/// keys of `granpack analyze`'s order section; in 2D it takes the 6 neighbours of a triangular
/// lattice (at a) and not the next shell (at sqrt(3) a).
inline constexpr double kOrderCutoff = 1.4;

/// 2D crystalline grains: |psi6| at least this. A convention of granpack, not a value of [AR]
/// or [GRC]: a triangular lattice gives 1, and for N_b independent isotropic bonds
/// P(|psi6| >= x) ~ exp(-N_b x^2), so 0.7 flags about 5 % of a gas's grains with 6 bonds
/// (0.45 would flag 30 %). docs/visualisation.md.
inline constexpr double kCrystallinePsi6 = 0.7;

/// The bonds of one owned grain: r_ij (real, to the nearest image) and j's id, in ascending id.
template <int dim> struct GrainBonds {
  GlobalId id = 0;
  std::vector<Vec<dim>> bonds;
  std::vector<GlobalId> neighbor_ids;
};

/// The bonds |r_ij| < d_c of every owned grain of `p`, found among owned grains and ghosts
/// (a layer at least d_c wide; a grain's own periodic images are not its neighbours).
template <int dim>
std::vector<GrainBonds<dim>> grain_bonds(const Cell<dim>& cell, const ParticleStore<dim>& p,
                                         double d_c);

/// |psi6| of bond vectors (2D), summed in the given order; 0 without bonds.
double psi6_modulus(std::span<const Vec<2>> bonds);

extern template std::vector<GrainBonds<2>> grain_bonds<2>(const Cell<2>&, const ParticleStore<2>&,
                                                          double);
extern template std::vector<GrainBonds<3>> grain_bonds<3>(const Cell<3>&, const ParticleStore<3>&,
                                                          double);

} // namespace granpack
