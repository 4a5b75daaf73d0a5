// `aggregate` stage: [GRC] method 2's aggregation (sec. III B). The grains get Maxwell
// velocities of rms V0 = velocity_ratio x V*, V* = sqrt(F0 D0 / m) (eq. 7, m the mass of a
// grain of diameter a), with zero total momentum and no spin, and move in the fixed cell
// under the cohesive law until every grain belongs to a single cluster of interacting grains
// and the packing meets the II D criteria (force, moment, kinetic energy on F1 = F0; the
// cell being fixed, there is no stress criterion). The next stage (`compress` at P* = 0 or
// 0.01) lets the cell go.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>

#include "granpack/comm/clusters.h"
#include "granpack/comm/reduce.h"
#include "granpack/contact/derived_constants.h"
#include "granpack/core/error.h"
#include "granpack/engine/checkpoint.h"
#include "granpack/engine/material_law.h"
#include "granpack/engine/md_engine.h"
#include "granpack/engine/stress_control.h"
#include "granpack/stages/stages.h"
#include "granpack/stages/state_metrics.h"

namespace granpack {

namespace {

/// Maxwell velocities drawn from the seed and each grain's id (the same on any rank count),
/// each component of variance V0^2/dim, then the mean velocity removed.
template <int dim>
void draw_maxwell_velocities(RunContext<dim>& ctx, double v0, std::uint64_t seed) {
  auto& p = ctx.system.particles;
  Vec<dim> momentum = Vec<dim>::Zero();
  double mass = 0;
  for (std::size_t i = 0; i < p.n_owned(); ++i) {
    std::mt19937_64 rng(seed * 0x9E3779B97F4A7C15ULL + static_cast<std::uint64_t>(p.id[i]));
    std::normal_distribution<double> normal(0.0, v0 / std::sqrt(double(dim)));
    for (int a = 0; a < dim; ++a)
      p.velocity[i][a] = normal(rng);
    p.angular_velocity[i].setZero();
    momentum += p.mass[i] * p.velocity[i];
    mass += p.mass[i];
  }
  global_sum_in_place(ctx.world, std::span<double>(momentum.data(), dim));
  mass = global_sum(ctx.world, mass);
  const Vec<dim> drift = momentum / mass;
  for (std::size_t i = 0; i < p.n_owned(); ++i)
    p.velocity[i] -= drift;
}

template <int dim> std::int64_t clusters_of(RunContext<dim>& ctx, const MdEngine<dim>& engine) {
  std::vector<std::pair<GlobalId, GlobalId>> pairs;
  const auto& id = ctx.system.particles.id;
  engine.for_each_contact([&](std::size_t i, std::size_t j, const Vec<dim>&,
                              const ContactState<dim>&) { pairs.emplace_back(id[i], id[j]); });
  return count_clusters(pairs, ctx.deck->sample.n, ctx.world);
}

} // namespace

template <int dim> StageReport run_stage(RunContext<dim>& ctx, const AggregateStage& g) {
  using clock = std::chrono::steady_clock;
  const auto t0 = clock::now();
  const auto& sample = ctx.deck->sample;
  const ContactLawParams& mat = ctx.contact_law;
  const double a = sample.diameter;
  if (!(mat.cohesion_force > 0))
    throw InputError(
        ctx.deck->file + ": stage[" + std::to_string(ctx.stage_index) +
        "] (aggregate) needs cohesion: set [material] cohesion_force and cohesion_range");
  GRANPACK_CHECK(ctx.decomposition,
                 "stage " << ctx.stage_index << " (aggregate): there is no sample yet");
  const double grain_mass = reference_grain_mass(ctx);
  const double f0 = mat.cohesion_force;
  const double v_star = cohesive_velocity_scale(f0, mat.cohesion_range, grain_mass);
  const double v0 = g.velocity_ratio * v_star;

  MdSettings<dim> s = deck_md_settings(ctx);
  // The force scale of the contacts is F0 (P* << 1): time step from a contact loaded by ~5 F0.
  s.dt = ctx.deck->numerics.time_step_fraction *
         contact_duration(mat, ctx.deck->material.density, sample, dim, f0 / grain_section(dim, a));
  s.stress_control = false;
  for (int k = 0; k < dim; ++k)
    s.cell.fixed[k] = true; // no stress criterion either

  const nlohmann::json resume = ctx.take_resume_frame();
  std::int64_t first_step = ctx.system.step;
  double first_time = ctx.system.time;
  std::int64_t clusters = -1, last_quench = 0, quenches = 0;
  std::int64_t one_cluster_step = -1; // first step at which a count found one cluster
  if (!resume.is_null()) {
    first_step = resume.at("first_step").get<std::int64_t>();
    first_time = exact_double(resume.at("first_time"));
    clusters = resume.at("clusters").get<std::int64_t>();
    // Absent from checkpoints written before quenches existed (then there were none).
    last_quench = resume.value("last_quench", std::int64_t(0));
    quenches = resume.value("quenches", std::int64_t(0));
    one_cluster_step = resume.value("one_cluster_step", std::int64_t(-1));
  } else {
    ctx.system.cell.rate.setZero();
    draw_maxwell_velocities(ctx, v0, g.seed);
  }
  {
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  "  V0 = %.4g V* = %.4g m/s (V* = %.4g m/s), fixed cell at phi %.5f, F0 = %.4g N, "
                  "dt = %.4g s",
                  g.velocity_ratio, v0, v_star, ctx.solid_fraction(), f0, s.dt);
    ctx.log->info(buf);
  }
  StageFrame<dim> frame(ctx, [&] {
    return nlohmann::json{{"stage", "aggregate"},
                          {"first_step", first_step},
                          {"first_time", exact(first_time)},
                          {"clusters", clusters},
                          {"last_quench", last_quench},
                          {"quenches", quenches},
                          {"one_cluster_step", one_cluster_step}};
  });
  MdEngine<dim> engine(ctx, make_contact_law<dim>(mat), s);
  const EquilibriumScales scales = EquilibriumScales::of(dim, a, 0.0, f0);
  const bool with_moment = g.tolerance.checks_moment();
  EquilibriumMeasure m = engine.measure(scales, with_moment);
  bool done = false;
  auto last_log = clock::now();
  std::int64_t last_log_step = ctx.system.step;
  while (true) {
    const std::int64_t steps = ctx.system.step - first_step;
    if (steps % g.cluster_every == 0)
      clusters = clusters_of(ctx, engine);
    if (clusters == 1 && one_cluster_step < 0)
      one_cluster_step = ctx.system.step;
    // After a quench the kinetic energy needs time to show what the forces do: the criteria
    // are tried only half a quench interval or more after the last one.
    const bool settled =
        last_quench == 0 || 2 * (ctx.system.step - last_quench) >= g.quench_interval;
    if (steps % 50 == 0) {
      m = engine.measure(scales, with_moment);
      if (settled && m.satisfies(g.tolerance)) {
        clusters = clusters_of(ctx, engine);
        if (clusters == 1) {
          done = true;
          break;
        }
      }
    }
    // One cluster: the aggregation is over and what moves are the floppy aggregate's slow,
    // nearly undamped motions (mechanisms, tangential and rolling oscillations: the model has
    // no tangential damping). Zeroing every velocity now and then drains them ([AR] sec. III
    // uses the same quench as a test of a static packing); the criteria are judged before a
    // quench and then on the motion that follows (never on the zeroed velocities).
    if (g.quench_interval > 0 && clusters == 1 && steps % 50 == 0 &&
        ctx.system.step - one_cluster_step >= g.quench_delay &&
        ctx.system.step - last_quench >= g.quench_interval) {
      auto& p = ctx.system.particles;
      for (std::size_t i = 0; i < p.size(); ++i) {
        p.velocity[i].setZero();
        p.angular_velocity[i].setZero();
      }
      if (last_quench == 0)
        ctx.log->progress("  step " + std::to_string(ctx.system.step) +
                          ": velocity quenches from now on (one cluster since step " +
                          std::to_string(one_cluster_step) + ")");
      last_quench = ctx.system.step;
      ++quenches;
    }
    if (g.max_steps > 0 && steps >= g.max_steps)
      break;
    if (steps % ctx.deck->output.log_every == 0) {
      const auto now = clock::now();
      const double secs = std::chrono::duration<double>(now - last_log).count();
      const double rate = secs > 0 ? double(ctx.system.step - last_log_step) / secs : 0.0;
      char buf[256];
      std::snprintf(buf, sizeof buf,
                    "  step %10lld  t %.4e s  clusters %lld  Fmax/F1 %.2e  Gmax/F1a %.2e  "
                    "Ek/F1a %.2e  contacts %lld  %.0f steps/s",
                    static_cast<long long>(ctx.system.step), ctx.system.time,
                    static_cast<long long>(clusters), m.force, m.moment, m.kinetic,
                    static_cast<long long>(engine.observables().contacts), rate);
      ctx.log->progress(buf);
      last_log = now;
      last_log_step = ctx.system.step;
    }
    engine.step();
  }

  const CohesiveCoordination cc =
      cohesive_coordination(ctx, engine, g.tolerance.force * scales.force);
  StageReport r;
  r.steps = ctx.system.step - first_step;
  r.time = ctx.system.time - first_time;
  r.equilibrated = done;
  r.phi = ctx.solid_fraction();
  r.pressure = engine.observables().stress_elastic.trace() / dim;
  r.z = cc.z;
  r.values = {{"clusters", double(clusters)},
              {"velocity_ratio", g.velocity_ratio},
              {"quenches", double(quenches)},
              {"v_star", v_star},
              {"z_interactions", cc.z},
              {"z_plus", cc.z_plus},
              {"z_minus", cc.z_minus},
              {"z_zero", cc.z_zero},
              {"distant_fraction", cc.distant_fraction}};
  {
    char buf[256];
    std::snprintf(
        buf, sizeof buf,
        "  %s: %lld cluster(s), phi %.6f, z %.4f (z+ %.4f, z- %.4f, z0 %.4f), t = %.4g T0",
        done ? "aggregated and equilibrated" : "NOT done (max_steps reached)",
        static_cast<long long>(clusters), *r.phi, cc.z, cc.z_plus, cc.z_minus, cc.z_zero,
        r.time / cohesive_time_scale(f0, a, grain_mass));
    ctx.log->info(buf);
  }
  r.wall_seconds = std::chrono::duration<double>(clock::now() - t0).count();
  return r;
}

template StageReport run_stage<2>(RunContext<2>&, const AggregateStage&);
template StageReport run_stage<3>(RunContext<3>&, const AggregateStage&);

} // namespace granpack
