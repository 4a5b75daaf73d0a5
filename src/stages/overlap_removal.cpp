// Overlap removal for freshly placed random grains: steepest descent of the elastic energy
// of a soft, frictionless linear repulsion at fixed cell, done with the MD engine by zeroing
// velocities after every step (each step then moves a grain by F dt^2 / 2m). Far below
// jamming a zero-overlap state is close by and the overlaps decay geometrically.
#include <cmath>
#include <limits>
#include <numbers>

#include "granpack/core/error.h"
#include "granpack/engine/material_law.h"
#include "granpack/engine/md_engine.h"
#include "granpack/stages/stages.h"

namespace granpack {

template <int dim> StageReport remove_overlaps(RunContext<dim>& ctx) {
  const auto& sample = ctx.deck->sample;
  ContactLawParams soft;
  soft.normal = NormalLawKind::kLinear;
  soft.k_n = 1.0; // the quench makes the result independent of its value
  soft.tangential = TangentialStiffnessKind::kRatio;
  soft.k_t_ratio = 0.0;
  soft.friction = 0.0;
  soft.damping_ratio = 0.0;
  MdSettings<dim> s;
  // dt^2 K / m* = 0.4: each step removes a large fraction of an isolated overlap, stably.
  s.dt = 0.2 * contact_duration(soft, ctx.deck->material.density, sample, dim, 1.0);
  s.skin = 0.2 * sample.diameter;
  s.stress_control = false;
  s.max_overlap = std::numeric_limits<double>::infinity(); // removing them is the point
  // Deep overlaps push grains far in one step; velocities are quenched after every step.
  s.max_step_displacement = std::numeric_limits<double>::infinity();
  MdEngine<dim> engine(ctx, make_contact_law<dim>(soft), s);
  const double target = 1e-9; // largest overlap / radius accepted
  const std::int64_t max_steps = 1000000;
  std::int64_t steps = 0;
  auto& p = ctx.system.particles;
  while (engine.observables().max_overlap > target) {
    GRANPACK_CHECK(steps < max_steps,
                   "stage " << ctx.stage_index << " (random): overlaps not removed after "
                            << max_steps << " steps (largest overlap/radius "
                            << engine.observables().max_overlap << "); lower phi");
    engine.step();
    for (std::size_t i = 0; i < p.n_owned(); ++i) {
      p.velocity[i].setZero();
      p.angular_velocity[i].setZero();
    }
    ++steps;
  }
  // The soft law's histories mean nothing to the next stage.
  ctx.system.contacts.clear();
  ctx.system.time = 0;
  ctx.log->info("  overlaps removed in " + std::to_string(steps) + " relaxation steps");
  StageReport r;
  r.steps = steps;
  return r;
}

template StageReport remove_overlaps<2>(RunContext<2>&);
template StageReport remove_overlaps<3>(RunContext<3>&);

} // namespace granpack
