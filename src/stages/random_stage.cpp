// `random` stage: grains at random positions in a cubic (square) cell at solid fraction phi,
// at rest, without overlaps. Two placements:
//  - relax (default): positions drawn uniformly (overlaps allowed), then the overlaps removed
//    by damped, frictionless MD at fixed cell with a soft linear repulsion
//    (stages/overlap_removal) until the largest overlap is below 1e-9 of a radius. Unlike random
//    sequential addition, which jams near Phi = 0.38 in 3D, this reaches the gas densities the
//    protocols need (Phi = 0.45 in [AR]), but leaves the formerly overlapping pairs touching.
//  - sequential: random sequential addition (neighbor/sequential_placement), no contacts; the
//    I-state of [GRC], where touching pairs would be bonded by cohesion from the start.
// Every rank draws all n positions from the same seeded stream and keeps its own, so the
// sample does not depend on the rank count.
#include <cmath>
#include <random>

#include "granpack/core/error.h"
#include "granpack/neighbor/sequential_placement.h"
#include "granpack/stages/stages.h"

namespace granpack {

template <int dim> StageReport run_stage(RunContext<dim>& ctx, const RandomStage& p) {
  const auto& sample = ctx.deck->sample;
  GRANPACK_CHECK(ctx.system.particles.size() == 0,
                 "stage " << ctx.stage_index << " (random) needs an empty sample");
  std::mt19937_64 rng(sample.seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  // Diameters first (the cell size depends on their total volume), then positions.
  std::vector<double> diameter(static_cast<std::size_t>(sample.n), sample.diameter);
  if (sample.distribution == "uniform")
    for (auto& d : diameter)
      d = sample.diameter *
          (sample.min_diameter_ratio + (1.0 - sample.min_diameter_ratio) * u(rng));
  double volume = 0;
  for (double d : diameter)
    volume += HomogeneousGrain<dim>::volume(d);
  const double side = std::pow(volume / p.phi, 1.0 / dim);
  ctx.system.cell.length = Vec<dim>::Constant(side);
  ctx.system.cell.rate.setZero();
  ctx.decomposition = std::make_unique<Decomposition<dim>>(ctx.world, ctx.system.cell.length);
  const bool sequential = p.placement == "sequential";
  std::vector<Vec<dim>> placed;
  if (sequential) {
    try {
      placed = place_sequentially<dim>(diameter, side, rng);
    } catch (const Error& e) {
      throw InputError("stage " + std::to_string(ctx.stage_index) +
                       " (random, placement = "
                       "\"sequential\", phi = " +
                       std::to_string(p.phi) + "): " + e.what() +
                       "; lower phi or use placement = \"relax\"");
    }
  }
  for (std::int64_t k = 0; k < sample.n; ++k) {
    Vec<dim> s;
    if (sequential)
      s = placed[static_cast<std::size_t>(k)];
    else
      for (int a = 0; a < dim; ++a)
        s[a] = u(rng);
    if (!ctx.decomposition->owns(s))
      continue;
    Particle<dim> q;
    q.id = k;
    const double d = diameter[static_cast<std::size_t>(k)];
    q.radius = 0.5 * d;
    q.mass = HomogeneousGrain<dim>::mass(ctx.deck->material.density, d);
    q.inertia = HomogeneousGrain<dim>::inertia(q.mass, d);
    q.position = s;
    ctx.system.particles.add_owned(q);
  }
  if (!sequential)
    return remove_overlaps(ctx);
  ctx.system.time = 0;
  ctx.log->info("  placed by random sequential addition");
  return StageReport{};
}

template StageReport run_stage<2>(RunContext<2>&, const RandomStage&);
template StageReport run_stage<3>(RunContext<3>&, const RandomStage&);

} // namespace granpack
