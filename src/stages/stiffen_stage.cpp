// `stiffen` stage: [GRC] series B (sec. III B 2). Aggregation is ten times cheaper with soft
// contacts (kappa = 1e2: the time step scales as 1/sqrt(K_N)); the equilibrated loose packing
// is then stiffened slowly to kappa = 1e4 under the prescribed stress. The normal stiffness
// grows geometrically in `increments` equal factors, each held for steps/increments time
// steps (a fixed number of contact durations, whatever K_N: each increment relaxes on the
// contact time scale). The rolling stiffness follows K_N (table I: K_r = 1e-4 a^2 K_N). The
// stage does not equilibrate: a `compress` stage after it does.
#include <chrono>
#include <cmath>
#include <cstdio>

#include "granpack/contact/derived_constants.h"
#include "granpack/core/error.h"
#include "granpack/engine/checkpoint.h"
#include "granpack/engine/material_law.h"
#include "granpack/engine/md_engine.h"
#include "granpack/engine/stress_control.h"
#include "granpack/stages/stages.h"
#include "granpack/stages/state_metrics.h"

namespace granpack {

template <int dim> StageReport run_stage(RunContext<dim>& ctx, const StiffenStage& g) {
  using clock = std::chrono::steady_clock;
  const auto t0 = clock::now();
  const auto& sample = ctx.deck->sample;
  const double a = sample.diameter;
  GRANPACK_CHECK(ctx.decomposition,
                 "stage " << ctx.stage_index << " (stiffen): there is no sample yet");
  if (ctx.contact_law.normal != NormalLawKind::kLinear)
    throw InputError(ctx.deck->file + ": stage[" + std::to_string(ctx.stage_index) +
                     "] (stiffen) needs [material] normal_law = \"linear\" (it ramps K_N)");

  const nlohmann::json resume = ctx.take_resume_frame();
  std::int64_t first_step = ctx.system.step;
  double first_time = ctx.system.time;
  double k_start = ctx.contact_law.k_n, kr_start = ctx.contact_law.rolling_stiffness;
  std::int64_t increment = 0;
  double cell_mass = 0;
  const bool resuming = !resume.is_null();
  if (resuming) {
    first_step = resume.at("first_step").get<std::int64_t>();
    first_time = exact_double(resume.at("first_time"));
    k_start = exact_double(resume.at("k_start"));
    kr_start = exact_double(resume.at("kr_start"));
    increment = resume.at("increment").get<std::int64_t>();
    cell_mass = exact_double(resume.at("cell_mass"));
  }
  const double ratio = g.normal_stiffness / k_start;
  const std::int64_t per = std::max<std::int64_t>(1, g.steps / g.increments);
  const double f0 = ctx.contact_law.cohesion_force;
  auto kappa_of = [&](double k) {
    return f0 > 0 ? a * k / f0
                  : stiffness_number(ctx.contact_law, sample, dim, ctx.stress_target.pressure);
  };
  {
    char buf[256];
    std::snprintf(
        buf, sizeof buf,
        "  K_N %.6g -> %.6g N/m (%s %.4g -> %.4g) in %lld increments of %lld steps, P = %.6g Pa",
        k_start, g.normal_stiffness, f0 > 0 ? "kappa = a K_N/F0" : "kappa", kappa_of(k_start),
        kappa_of(g.normal_stiffness), static_cast<long long>(g.increments),
        static_cast<long long>(per), g.control.pressure);
    ctx.log->info(buf);
  }
  StageFrame<dim> frame(ctx, [&] {
    return nlohmann::json{{"stage", "stiffen"},
                          {"first_step", first_step},
                          {"first_time", exact(first_time)},
                          {"k_start", exact(k_start)},
                          {"kr_start", exact(kr_start)},
                          {"increment", increment},
                          {"cell_mass", exact(cell_mass)}};
  });
  MdSettings<dim> s = deck_md_settings(ctx);
  s.stress_control = true;
  s.cell = cell_control_of(ctx, g.control);
  // The cell mass is fixed at the stage start (L0 then); a restart restores it bit for bit.
  if (resuming)
    s.cell.mass = cell_mass;
  cell_mass = s.cell.mass;
  const double load = g.control.pressure > 0 ? g.control.pressure : f0 / grain_section(dim, a);
  auto last_log = clock::now();
  std::int64_t last_log_step = ctx.system.step;
  for (; increment < g.increments; ++increment) {
    const double f = std::pow(ratio, double(increment + 1) / double(g.increments));
    ctx.contact_law.k_n = k_start * f;
    if (g.scale_rolling)
      ctx.contact_law.rolling_stiffness = kr_start * f;
    s.dt = ctx.deck->numerics.time_step_fraction *
           contact_duration(ctx.contact_law, ctx.deck->material.density, sample, dim, load);
    MdEngine<dim> engine(ctx, make_contact_law<dim>(ctx.contact_law), s);
    const std::int64_t end =
        first_step + (increment + 1 == g.increments ? g.steps : (increment + 1) * per);
    while (ctx.system.step < end)
      engine.step();
    const auto now = clock::now();
    if ((increment + 1) % std::max<std::int64_t>(1, g.increments / 10) == 0 ||
        increment + 1 == g.increments) {
      const double secs = std::chrono::duration<double>(now - last_log).count();
      char buf[256];
      std::snprintf(
          buf, sizeof buf,
          "  increment %lld/%lld: K_N %.4g N/m (kappa %.4g), phi %.5f, P %.4g Pa, contacts "
          "%lld, Ek %.3e J, %.0f steps/s",
          static_cast<long long>(increment + 1), static_cast<long long>(g.increments),
          ctx.contact_law.k_n, kappa_of(ctx.contact_law.k_n), ctx.solid_fraction(),
          engine.observables().stress_elastic.trace() / dim,
          static_cast<long long>(engine.observables().contacts),
          engine.observables().kinetic_energy,
          secs > 0 ? double(ctx.system.step - last_log_step) / secs : 0.0);
      ctx.log->progress(buf);
      last_log = now;
      last_log_step = ctx.system.step;
    }
  }
  StageReport r;
  r.steps = ctx.system.step - first_step;
  r.time = ctx.system.time - first_time;
  r.phi = ctx.solid_fraction();
  r.values = {{"normal_stiffness_start", k_start},
              {"normal_stiffness", ctx.contact_law.k_n},
              {"rolling_stiffness", ctx.contact_law.rolling_stiffness},
              {"kappa_start", kappa_of(k_start)},
              {"kappa", kappa_of(ctx.contact_law.k_n)}};
  r.wall_seconds = std::chrono::duration<double>(clock::now() - t0).count();
  return r;
}

template StageReport run_stage<2>(RunContext<2>&, const StiffenStage&);
template StageReport run_stage<3>(RunContext<3>&, const StiffenStage&);

} // namespace granpack
