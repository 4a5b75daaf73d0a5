#pragma once
// A configuration file loaded for analysis: the grains distributed over the ranks with a
// ghost layer of a chosen width, the contacts with both grains located, and the force-
// carrying backbone (iterative rattler rule of [AR] sec. III B). The analysis sections of
// `granpack analyze` (app/analyze_*.cpp) all read from it. Collective on world.
#include <mpi.h>

#include <filesystem>
#include <memory>

#include "granpack/comm/backbone.h"
#include "granpack/comm/decomposition.h"
#include "granpack/comm/halo.h"
#include "granpack/contact/contact_law.h"
#include "granpack/core/system.h"
#include "granpack/io/deck.h"
#include "granpack/io/hdf5_store.h"

namespace granpack {

/// One contact of the file, owned by this rank: local indices (i owned, j the nearest image).
template <int dim> struct ContactView {
  std::size_t i = 0, j = 0;
  Vec<dim> branch;           ///< r_j - r_i (real)
  double normal_force = 0;   ///< N^e
  Vec<dim> tangential_force; ///< T
  double attraction = 0;     ///< N^a of [GRC] eq. 4-5 (0 without cohesion), from the geometry
  bool distant = false;      ///< a cohesive pair across a gap (flag kDistant): N^e = T = 0
  RotVec<dim> rolling =
      RotVec<dim>::Zero(); ///< elastic relative rotation δθ of j from i ([GRC] eq. 9)
  double total_normal_force() const { return normal_force + attraction; }
};

template <int dim> struct PackingView {
  MPI_Comm world = MPI_COMM_WORLD;
  Deck deck; ///< the deck stored in the file (its sample)
  /// The contact law and stress target in force when the file was written (its /parameters;
  /// for older files, replayed from the deck: replayed_parameters).
  ContactLawParams contact_law;
  StressTarget stress_target;
  ContactLaw<dim> law; ///< make_contact_law(contact_law)
  double diameter = 0; ///< a
  System<dim> system;
  std::unique_ptr<Decomposition<dim>> decomposition;
  Halo<dim> halo;
  double ghost_width = 0;       ///< real width of the ghost layer
  double phi = 0, pressure = 0; ///< solid fraction; static pressure tr(sigma)/dim (N^e + N^a, T)
  Tensor<dim> stress = Tensor<dim>::Zero();
  double force_threshold =
      0; ///< N above which N^e carries force: threshold x a^2 P, x F1 with cohesion
  std::vector<ContactView<dim>> contacts;
  std::vector<CarryingContact> carrying; ///< N > threshold
  Backbone backbone; ///< rattler flags and counts per local grain (ghosts copied)
  /// false: the backbone is [AR]'s force-carrying one (N^e above the threshold); true: the
  /// whole interaction network of [GRC] sec. III (every contact and distant pair, whatever
  /// its force; only isolated grains are left out), see select_interaction_network.
  bool interaction_network = false;
  std::int64_t detached_clusters = 0, detached_grains = 0; ///< left out of the network
  std::int64_t n = 0;

  const ParticleStore<dim>& particles() const { return system.particles; }
  bool rattler(std::size_t i) const { return backbone.rattler[i] != 0; }
};

/// Reads `file` and builds the view with ghosts within `reach` diameters a (at least the
/// contact range 2 R_max). threshold: force-carrying threshold / (a^(dim-1) P).
template <int dim>
PackingView<dim> load_packing(MPI_Comm world, const std::filesystem::path& file,
                              const FileMeta& meta, double threshold, double reach);

} // namespace granpack

namespace granpack {

/// Replaces the backbone by the whole interaction network ([GRC] sec. III: with cohesion "the
/// whole interacting contact network is to be considered" for rigidity, since a contact at
/// h = h0 carries N = 0 but still has stiffness K_N): every stored contact and distant pair
/// of the largest connected cluster counts. Grains outside it are flagged as rattlers: the
/// isolated ones and those of smaller clusters (detached_clusters, detached_grains), whose
/// rigid-body motions would otherwise count as mechanisms of the packing. Collective.
template <int dim> void select_interaction_network(PackingView<dim>& v);

/// Calls f(i, j, r_ij, |r_ij|) for every owned grain i and every local grain j (owned or
/// ghost, j not an image of i) closer than `cutoff` (<= the view's ghost width), r_ij = r_j - r_i.
template <int dim, class F> void for_each_neighbor(const PackingView<dim>& v, double cutoff, F&& f);

} // namespace granpack

#include "granpack/packing/packing_view_neighbors.h"
