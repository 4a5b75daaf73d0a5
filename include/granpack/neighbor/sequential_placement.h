#pragma once
// Random sequential addition (RSA) of spheres (disks) in a periodic cube (square): each grain
// is tried at uniformly random positions until it overlaps none of those already placed.
//
// Why: [GRC]'s I-state is "random non-overlapping positions ... with zero velocity". Removing
// the overlaps of uniformly drawn grains (the `relax` placement) leaves every formerly
// overlapping pair exactly in contact - about 1.3 contacts per disk at Phi = 0.36 - and with
// cohesion those pairs are bonded before the protocol starts. RSA leaves a continuous
// distribution of gaps, with almost no pair closer than the attraction range D0.
//
// Grains go in by decreasing diameter (ties by index): small grains then fill the holes left
// between large ones, which reaches the 2D Phi_I = 0.52 of [GRC] quickly, whereas a random
// order slows down near it. Positions stay uniform and independent of the grain's index.
//
// MPI-free and deterministic for a given generator state: every rank runs the same placement
// and keeps its own grains, so the sample does not depend on the rank count.
#include <cstdint>
#include <random>
#include <vector>

#include "granpack/core/vec.h"

namespace granpack {

/// Scaled positions s in [0,1)^dim of grains with the given diameters in a periodic cube of
/// side `side`, no two overlapping (centre distance >= sum of radii). Throws granpack::Error
/// naming the grain and the solid fraction when a grain finds no room after
/// `max_attempts_per_grain` tries.
template <int dim>
std::vector<Vec<dim>> place_sequentially(const std::vector<double>& diameter, double side,
                                         std::mt19937_64& rng,
                                         std::int64_t max_attempts_per_grain = 10000000);

} // namespace granpack
