#pragma once
// Load balancing of the domain decomposition: moves the cut planes of each axis so that the
// ranks share the work (the "shift" balancing of LAMMPS' balance command, which keeps the
// Cartesian grid and so the halo's face neighbours). The work of a grain is a weight the
// caller gives (MdEngine: 2 + the Verlet-list pairs it takes part in); with no weights, grains
// count alike. Triggered by the engine at a neighbour-list rebuild (MdEngine::rebuild) when the
// loads are uneven. Every decision is a function of the positions, the weights, the cell and
// the cuts alone, never of a clock, so that a run restarted from a checkpoint (which stores the
// cuts) continues bit for bit. Collective on the decomposition's communicator.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "granpack/comm/decomposition.h"
#include "granpack/core/particles.h"

namespace granpack {

/// Largest load on a rank over the mean (1 when balanced, `size` when one rank has it all).
/// Collective.
double load_imbalance(MPI_Comm comm, std::int64_t local_load);

/// Grains on the fullest rank over the mean. Collective.
inline double grain_imbalance(MPI_Comm comm, std::size_t owned) {
  return load_imbalance(comm, static_cast<std::int64_t>(owned));
}

/// Cut planes that balance the weighted grains (weights: one per owned grain, or empty for 1
/// each) over the cells of the grid: every axis first at the quantiles of its weight, then,
/// axis by axis for a few rounds, the planes that minimise the heaviest cell given the other
/// axes' planes (core/cut_planes.h). Every slab at least min_width[a] of the cell length wide
/// (min_width[a] <= 1 / dims[a]). Collective.
template <int dim>
std::array<std::vector<double>, dim>
balanced_cuts(const Decomposition<dim>& d, const ParticleStore<dim>& p,
              std::span<const std::int64_t> weights, const Vec<dim>& min_width);

/// True when the planes have moved (not uniform) and a slab is narrower than ghost_width (the
/// cell shrank since they were placed): the halo needs new planes before it can be built.
template <int dim> bool planes_too_narrow(const Decomposition<dim>& d, const Vec<dim>& ghost_width);

/// New planes for the weighted grains (balanced_cuts), every slab at least `margin` x
/// ghost_width wide where the grid allows it. Returns true when they differ from the current
/// ones (set on d; the caller then migrates the grains). The caller decides when: a load
/// imbalance above its threshold, or planes_too_narrow. Collective.
template <int dim>
bool rebalance(Decomposition<dim>& d, const ParticleStore<dim>& p,
               std::span<const std::int64_t> weights, const Vec<dim>& ghost_width,
               double margin = 1.25);

} // namespace granpack
