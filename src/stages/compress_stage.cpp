// `compress` stage: stress-controlled MD with the contact law until the [AR] equilibrium
// criteria hold at the prescribed pressure ([AR] sec. II B, III).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>

#include "granpack/contact/derived_constants.h"
#include "granpack/core/error.h"
#include "granpack/dynamics/eta_estimate.h"
#include "granpack/engine/checkpoint.h"
#include "granpack/engine/material_law.h"
#include "granpack/engine/md_engine.h"
#include "granpack/engine/stress_control.h"
#include "granpack/stages/stages.h"
#include "granpack/stages/state_metrics.h"

namespace granpack {

namespace {
/// One progress line; the criteria are normalised by [AR]'s scales, or by F1 with cohesion
/// (the labels say which), and the moment is shown when it is a criterion.
std::string progress_line(std::int64_t step, double t, double phi, const EquilibriumMeasure& m,
                          std::int64_t contacts, double steps_per_s, bool cohesive,
                          bool with_moment) {
  char moment[48] = "";
  if (with_moment)
    std::snprintf(moment, sizeof moment, "  Gmax/F1a %.2e", m.moment);
  char buf[320];
  std::snprintf(buf, sizeof buf,
                cohesive ? "  step %10lld  t %.4e s  phi %.5f  |dP|a/F1 %.2e  Fmax/F1 %.2e%s  "
                           "Ek/F1a %.2e  contacts %lld  %.0f steps/s"
                         : "  step %10lld  t %.4e s  phi %.5f  |dP|/P %.2e  Fmax/a2P %.2e%s  "
                           "Ek/Pa3 %.2e  contacts %lld  %.0f steps/s",
                static_cast<long long>(step), t, phi, m.stress, m.force, moment, m.kinetic,
                static_cast<long long>(contacts), steps_per_s);
  return buf;
}
} // namespace

template <int dim> StageReport run_stage(RunContext<dim>& ctx, const CompressStage& c) {
  using clock = std::chrono::steady_clock;
  const auto t0 = clock::now();
  const auto& sample = ctx.deck->sample;
  const double a = sample.diameter, P = c.pressure;
  const double grain_mass = reference_grain_mass(ctx);
  GRANPACK_CHECK(ctx.decomposition,
                 "stage " << ctx.stage_index << " (compress): there is no sample yet");

  const double f0 = ctx.contact_law.cohesion_force;
  MdSettings<dim> s = deck_md_settings(ctx);
  // The time step: contacts loaded by 5 a^2 P, or by 5 F0 under P* = 0 ([GRC] relaxation).
  const double load = P > 0 ? P : f0 / grain_section(dim, a);
  s.dt = ctx.deck->numerics.time_step_fraction *
         contact_duration(ctx.contact_law, ctx.deck->material.density, sample, dim, load);
  s.stress_control = true;
  s.cell = cell_control_of(ctx, c);
  // Inertia number I = eps_dot sqrt(m / (a P)) (eq. 23) of the strain rate reached; none at P = 0.
  const double inertia_time = P > 0 ? std::sqrt(grain_mass / ((dim == 3 ? a : 1.0) * P)) : 0.0;

  // kappa = K_N/P (or (E~/P)^(2/3)) is undefined at P = 0; [GRC]'s a K_N / F0 is logged.
  const std::optional<double> kappa =
      P > 0 ? std::optional<double>(stiffness_number(ctx.contact_law, sample, dim, P))
            : std::nullopt;
  {
    char buf[256];
    std::snprintf(
        buf, sizeof buf,
        "  P = %.6g Pa, kappa = %.6g, mu = %g, zeta = %g, I_max = %s, strain rate max = %s, "
        "M = %g x grain mass%s, dt = %.4g s",
        P, kappa.value_or(std::numeric_limits<double>::infinity()), ctx.contact_law.friction,
        ctx.contact_law.damping_ratio,
        c.inertia_max ? std::to_string(*c.inertia_max).c_str() : "none",
        std::isfinite(s.cell.max_strain_rate)
            ? (std::to_string(s.cell.max_strain_rate) + " 1/s").c_str()
            : "none",
        c.cell_mass, c.cell_mass_per_length ? " x a/L0" : "", s.dt);
    ctx.log->info(buf);
    const ContactLawParams& mat = ctx.contact_law;
    if (mat.cohesion_force > 0) {
      // [GRC] sec. II C: P* = P a^(dim-1) / F0 and kappa = a K_N / F0 (Hertz: (E~ a^2/F0)^(2/3)).
      const double kappa_f0 = mat.normal == NormalLawKind::kLinear
                                  ? a * mat.k_n / f0
                                  : hertz_cohesive_stiffness_number(
                                        e_tilde_of(mat.young_modulus, mat.poisson_ratio), a, f0);
      std::snprintf(buf, sizeof buf,
                    "  cohesion: F0 = %.6g N, D0/a = %.3g, P* = %.6g, kappa = a K_N/F0 = %.6g, "
                    "V* = sqrt(F0 D0 / m) = %.4g m/s, T0 = sqrt(m a / F0) = %.4g s",
                    f0, mat.cohesion_range / a, pressure_force(dim, a, P) / f0, kappa_f0,
                    cohesive_velocity_scale(f0, mat.cohesion_range, grain_mass),
                    cohesive_time_scale(f0, a, grain_mass));
      ctx.log->info(buf);
    }
    if (mat.rolling_stiffness > 0) {
      std::snprintf(buf, sizeof buf,
                    "  rolling resistance: K_r = %.6g N m, mu_r/a = %.4g, zeta_r = %g",
                    mat.rolling_stiffness, mat.rolling_friction / a, mat.rolling_damping);
      ctx.log->info(buf);
    }
  }

  // [AR] sec. III scales (a^2 P, P, P a^3), or [GRC] II D's built on F1 = max(F0, P a).
  const EquilibriumScales scales = EquilibriumScales::of(dim, a, P, ctx.contact_law.cohesion_force);
  const double force_scale = scales.force;
  const bool with_moment = c.tolerance.checks_moment();
  const bool cohesive = ctx.contact_law.cohesion_force > 0;
  const std::int64_t check_every = 50;
  const std::int64_t log_every = ctx.deck->output.log_every;
  std::int64_t first_step = ctx.system.step;
  double first_time = ctx.system.time;
  double inertia_reached = 0;
  bool equilibrated = false;
  std::int64_t last_quench = -c.quench_interval, quenches = 0;
  // Restart inside this stage: the loop's state as the checkpoint left it. The cell mass is
  // restored too: a sum over grains in another order could differ in its last bit.
  const nlohmann::json resume = ctx.take_resume_frame();
  const bool resuming = !resume.is_null();
  if (resuming) {
    first_step = resume.at("first_step").get<std::int64_t>();
    first_time = exact_double(resume.at("first_time"));
    inertia_reached = exact_double(resume.at("inertia_reached"));
    last_quench = resume.at("last_quench").get<std::int64_t>();
    quenches = resume.at("quenches").get<std::int64_t>();
    s.cell.mass = exact_double(resume.at("cell_mass"));
    // A zero or negative cell mass never reaches the target stress (the run would not end).
    if (!(s.cell.mass > 0) || !std::isfinite(s.cell.mass))
      throw InputError("the --restart checkpoint's compress frame holds cell_mass = " +
                       std::to_string(s.cell.mass) +
                       " kg (need a positive finite mass): a damaged checkpoint");
  }
  StageFrame<dim> frame(ctx, [&] {
    return nlohmann::json{{"stage", "compress"},
                          {"first_step", first_step},
                          {"first_time", exact(first_time)},
                          {"inertia_reached", exact(inertia_reached)},
                          {"last_quench", last_quench},
                          {"quenches", quenches},
                          {"cell_mass", exact(s.cell.mass)}};
  });
  MdEngine<dim> engine(ctx, make_contact_law<dim>(ctx.contact_law), s);
  EquilibriumMeasure m = engine.measure(scales, with_moment);
  auto last_log = clock::now();
  std::int64_t last_log_step = ctx.system.step;
  EtaEstimate eta(c.tolerance);
  // On a mid-step restart the engine has just completed the interrupted step: continue after
  // the engine.step() call of the loop below.
  bool after_step = resuming;
  while (true) {
    if (after_step) {
      after_step = false;
      for (int k = 0; k < dim; ++k)
        inertia_reached =
            std::max(inertia_reached,
                     std::abs(ctx.system.cell.rate[k] / ctx.system.cell.length[k]) * inertia_time);
      continue;
    }
    const std::int64_t done = ctx.system.step - first_step;
    if (done % check_every == 0) {
      m = engine.measure(scales, with_moment);
      // After an unconditional quench the motion needs time to show what the forces do.
      const bool settled = !c.quench_always || quenches == 0 ||
                           2 * (ctx.system.step - last_quench) >= c.quench_interval;
      if (settled && m.satisfies(c.tolerance)) {
        equilibrated = true;
        break;
      }
      // [AR] sec. III: a static packing whose velocities are set to zero must not regain
      // kinetic energy. Quenching lets the criteria be met when the remaining energy sits
      // in nearly undamped modes (free rolling of divalent grains, rattlers in their cages).
      if (c.quench_interval > 0 && (c.quench_always || m.static_state(c.tolerance)) &&
          ctx.system.step - last_quench >= c.quench_interval) {
        auto& p = ctx.system.particles;
        for (std::size_t i = 0; i < p.size(); ++i) {
          p.velocity[i].setZero();
          p.angular_velocity[i].setZero();
        }
        if (c.quench_always)
          ctx.system.cell.rate.setZero();
        last_quench = ctx.system.step;
        ++quenches;
        if (!c.quench_always)
          ctx.log->progress("  step " + std::to_string(ctx.system.step) +
                            ": static (force and stress criteria hold), velocities set to zero");
        else if (quenches == 1)
          ctx.log->progress("  step " + std::to_string(ctx.system.step) +
                            ": velocities and cell rate set to zero every " +
                            std::to_string(c.quench_interval) + " steps from now on");
      }
    }
    if (c.max_steps > 0 && done >= c.max_steps)
      break;
    if (done % log_every == 0) {
      const auto now = clock::now();
      const double secs = std::chrono::duration<double>(now - last_log).count();
      const double rate = secs > 0 ? double(ctx.system.step - last_log_step) / secs : 0.0;
      const double phi = ctx.solid_fraction();
      ctx.log->progress(
          progress_line(ctx.system.step, ctx.system.time, phi, m, engine.observables().contacts,
                        rate, cohesive, with_moment) +
          eta.update(m, ctx.system.step, rate, c.max_steps > 0 ? first_step + c.max_steps : -1));
      last_log = now;
      last_log_step = ctx.system.step;
    }
    engine.step();
    after_step = true;
  }
  ctx.log->progress(progress_line(ctx.system.step, ctx.system.time, ctx.solid_fraction(), m,
                                  engine.observables().contacts, 0.0, cohesive, with_moment));

  const int min_contacts = min_backbone_contacts(dim, ctx.contact_law.friction);
  const StateMetrics sm = state_metrics(ctx, engine, c.tolerance.force * force_scale, min_contacts);
  StageReport r;
  r.steps = ctx.system.step - first_step;
  r.time = ctx.system.time - first_time;
  r.equilibrated = equilibrated;
  r.phi = ctx.solid_fraction();
  r.pressure = engine.observables().stress_elastic.trace() / dim;
  r.kappa = kappa;
  if (P > 0)
    r.inertia_max = inertia_reached;
  r.z = sm.z;
  r.z_star = sm.z_star;
  r.x0 = sm.x0;
  r.x2 = sm.x2;
  r.z2 = sm.z2;
  if (c.quench_interval > 0)
    r.values.emplace_back("quenches", double(quenches));
  if (cohesive) {
    const CohesiveCoordination cc =
        cohesive_coordination(ctx, engine, c.tolerance.force * force_scale);
    r.values.emplace_back("z_interactions", cc.z);
    r.values.emplace_back("z_plus", cc.z_plus);
    r.values.emplace_back("z_minus", cc.z_minus);
    r.values.emplace_back("z_zero", cc.z_zero);
    r.values.emplace_back("distant_fraction", cc.distant_fraction);
    char buf[200];
    std::snprintf(buf, sizeof buf,
                  "  interactions ([GRC]): z %.4f = z+ %.4f + z- %.4f + z0 %.4f, distant %.2f %%",
                  cc.z, cc.z_plus, cc.z_minus, cc.z_zero, 100 * cc.distant_fraction);
    ctx.log->info(buf);
  }
  ctx.stress_target = StressTarget{ctx.stage_index, c.stress, c.fixed, P};
  {
    char buf[320];
    std::snprintf(
        buf, sizeof buf,
        "  %s: phi %.6f, P %.6g Pa, z %.4f, z* %.4f, x0 %.4f, x2 %.4f, Z(2) %.4f, I reached %.3g, "
        "%lld list rebuilds",
        equilibrated ? "equilibrated" : "NOT equilibrated (max_steps reached)", *r.phi, *r.pressure,
        sm.z, sm.z_star, sm.x0, sm.x2, sm.z2, inertia_reached,
        static_cast<long long>(engine.rebuilds()));
    ctx.log->info(buf);
  }
  r.wall_seconds = std::chrono::duration<double>(clock::now() - t0).count();
  return r;
}

template StageReport run_stage<2>(RunContext<2>&, const CompressStage&);
template StageReport run_stage<3>(RunContext<3>&, const CompressStage&);

} // namespace granpack
