#pragma once
// The contact network as something to look at: per contact the segment between the two
// centres (drawn to the periodic image of the second grain, never across the cell), the static
// normal force N = N^e + N^a, |T| and a class (compressive, tensile, distant, unstressed); per
// grain the contact counts, the net static force and moment. Written into configuration files and
// shown by their XDMF sidecar (docs/visualisation.md, docs/hdf5-schema.md "/network").
//
// One rank's contacts over its local particles (owned + ghosts); per-grain sums land on the
// ghost entries too and are added into their owners by the caller (engine/network_fields).
// MPI-free.
#include <array>
#include <cstdint>
#include <numbers>
#include <vector>

#include "granpack/analysis/coordination.h"
#include "granpack/contact/contact_law.h"
#include "granpack/core/cell.h"
#include "granpack/core/contact_store.h"
#include "granpack/core/particles.h"

namespace granpack {

/// Class of an interaction in /network/kind (the colours of jobs/tools/plot_2d.py).
enum class NetworkKind : std::int64_t {
  kCompressive = 0, ///< N > 0
  kTensile = 1,     ///< N < 0, in contact (cohesion)
  kDistant = 2,     ///< a cohesive pair across a gap (N < 0)
  kUnstressed = 3,  ///< N = 0
};

template <int dim> struct NetworkFields {
  // Per contact, in the order of the ContactStore:
  std::vector<Vec<dim>> start;              ///< centre of `first`, folded into the cell (m)
  std::vector<Vec<dim>> end;                ///< start + r_12, the nearest image of `second` (m)
  std::vector<double> normal_force;         ///< N = N^e + N^a (N; > 0 repulsive)
  std::vector<double> tangential_magnitude; ///< |T| (N)
  std::vector<std::int64_t> kind;           ///< NetworkKind
  /// |T| / (μ N^e), the friction mobilised (1: at the Coulomb limit, sliding); 0 where the limit
  /// μ N^e is 0 (no friction, N^e <= 0) or infinite.
  std::vector<double> mobilisation;
  /// 1 for a contact of the strong network (N > <N>, the mean over the compressive contacts of
  /// every rank: [AR]'s strong/weak split), else 0. Not filled by contact_network (the mean is
  /// global: engine/network_fields.h).
  std::vector<double> strong;
  // Per local particle (owned, then ghosts: partial sums for their owners):
  std::vector<double> contacts;                   ///< contacts (distant pairs not counted)
  std::vector<double> carrying_contacts;          ///< contacts with N^e > 0
  std::array<std::vector<double>, dim> net_force; ///< sum of the static contact forces (N)
  /// Sum of the static contact moments about the grain's centre (N m; 2D: about z, per metre
  /// of thickness): b x f of each contact force f applied at the contact point (branch b =
  /// (R - h/2) n towards the partner, as ContactLaw::force and the engine's elastic moments),
  /// plus [GRC]'s elastic rolling moment -K_r dtheta on `second` (+K_r dtheta on `first`).
  /// ≈ 0 in equilibrium. Over the grains, sum_g net_moment_g = -sum_c r_12 x f_c (f on
  /// `second`): the rolling moments cancel pairwise, what remains is the antisymmetric part of
  /// the contact virial.
  std::array<std::vector<double>, rot_dim<dim>> net_moment;
  /// The grain's mean static stress (Pa): tr of its share of the virial over its volume,
  /// (1/(dim V_g)) sum over its contacts of f.r_12 / 2 (V_g = pi R^2 per unit thickness in 2D,
  /// 4 pi R^3 / 3 in 3D); sum_g V_g mean_stress_g / V is the static pressure.
  std::vector<double> mean_stress;
  /// The grain's static stress tensor (Pa), sigma_ab = (1/V_g) sum over its contacts of
  /// f_a r_12,b / 2 (f the force on `second`, r_12 the branch vector), component a * dim + b:
  /// each contact's share of the cell's virial f (x) r_12 split evenly between its two grains,
  /// as mean_stress splits its trace, so tr(sigma)/dim = mean_stress and
  /// sum_g V_g sigma_g = V sigma (the static stress of the cell, granpack_io.py stress()).
  /// Compressive positive. Not symmetric in general (tangential forces, unequal radii).
  std::array<std::vector<double>, dim * dim> stress;
  /// Per contact placed (distant pairs too): the local rows of its grains and N^e, what the
  /// backbone of [AR]'s rattler rule is found from (comm/backbone.h).
  std::vector<CarryingContact> pairs;
  /// Per owned grain: 1 for a rattler of the iterated rule, else 0. Not filled by
  /// contact_network (the rule runs across ranks: engine/network_fields.h).
  std::vector<double> rattler;
  /// Per owned grain: 1 for a rattler that the last fix_rattlers stage of the run pushed onto
  /// the backbone (treatment II of [AR] sec. III C: RunContext::fixed_rattlers), else 0. Not
  /// filled by contact_network.
  std::vector<double> fixed_rattler;
  /// Per owned grain: its cluster, the smallest id among the grains joined to it by the stored
  /// contacts (distant cohesive pairs included, as the aggregation of [GRC] counts clusters:
  /// comm/clusters.h); a grain without contacts is its own cluster. Not filled by
  /// contact_network (clusters span ranks: engine/network_fields.h, comm/cluster_ids.h).
  std::vector<std::int64_t> cluster_id;
  /// Per owned grain: local bond-orientational order within kOrderCutoff a
  /// (analysis/local_order.h), Q6 in 3D, |psi6| in 2D; 0 without bonds. Not filled by
  /// contact_network.
  std::vector<double> bond_order;
  /// Per owned grain: 1 for a crystalline grain (3D: [AR] eq. 34, at least 7 crystalline bonds;
  /// 2D: |psi6| >= kCrystallinePsi6), else 0. Not filled by contact_network.
  std::vector<double> crystalline;
  std::int64_t missing = 0; ///< contacts whose grains are not both local (nothing computed)

  /// Sizes the fields contact_network fills for `nc` contacts and `n` local grains, all zero
  /// (kind: unstressed), so that a contact or grain it skips reads as no force; the fields
  /// filled elsewhere are left as they are.
  void reset(std::size_t nc, std::size_t n) {
    start.assign(nc, Vec<dim>::Zero());
    end.assign(nc, Vec<dim>::Zero());
    normal_force.assign(nc, 0.0);
    tangential_magnitude.assign(nc, 0.0);
    kind.assign(nc, static_cast<std::int64_t>(NetworkKind::kUnstressed));
    mobilisation.assign(nc, 0.0);
    for (auto* v : {&contacts, &carrying_contacts, &mean_stress})
      v->assign(n, 0.0);
    for (auto& c : net_force)
      c.assign(n, 0.0);
    for (auto& c : net_moment)
      c.assign(n, 0.0);
    for (auto& c : stress)
      c.assign(n, 0.0);
  }
};

/// Volume of a grain of radius r: a disk per unit thickness in 2D, a sphere in 3D.
template <int dim> double grain_volume(double r) {
  return dim == 2 ? std::numbers::pi * r * r : 4.0 / 3.0 * std::numbers::pi * r * r * r;
}

/// `p`: owned grains and a ghost layer at least as wide as the contacts are long.
template <int dim>
NetworkFields<dim> contact_network(const Cell<dim>& cell, const ParticleStore<dim>& p,
                                   const ContactStore<dim>& contacts, const ContactLaw<dim>& law);

extern template NetworkFields<2> contact_network<2>(const Cell<2>&, const ParticleStore<2>&,
                                                    const ContactStore<2>&, const ContactLaw<2>&);
extern template NetworkFields<3> contact_network<3>(const Cell<3>&, const ParticleStore<3>&,
                                                    const ContactStore<3>&, const ContactLaw<3>&);

} // namespace granpack
