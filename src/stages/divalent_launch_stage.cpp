// `divalent_launch` stage: [AR] App. E's stability test of a divalent grain's free rolling.
// The packing is brought to rest, one divalent grain (stages/divalent_pick.h) is given the
// velocity and angular velocity of its rolling mechanism (analysis/divalent_launch.h, eqs.
// E1-E2), and MD runs under the prescribed stress, with every pair free to touch or, with
// frozen_network, only the pairs in contact at launch (MdSettings::pair_allowed). Rows of the
// trajectory (the grain's centre in [AR] fig. 16's (f, t) plane, its contact forces, the
// kinetic energies, the launch contacts still closed) go to a CSV file; the verdict follows
// docs/stiffness.md: collapsed when more than collapse_fraction of the launch contacts have
// opened, else rearranged when the kinetic energy exceeded energy_factor x the launch energy,
// else arrested when the grain's energy fell below 1 % of it or the grain no longer touches
// exactly its two neighbours at the end, else rolling. The run ends after
// its turns, or at the first collapse (stop_on = "collapse") or rearrangement ("rearrangement").
// A collapse under stop_on = "rearrangement" is then not awaited: with a frozen network the
// energy can only come from the work of the stress on a failing network.
// The stage is not resumable mid-run (no checkpoint frame): a restart repeats it.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>

#include "granpack/comm/communicator.h"
#include "granpack/comm/reduce.h"
#include "granpack/core/error.h"
#include "granpack/engine/material_law.h"
#include "granpack/engine/stress_control.h"
#include "granpack/stages/divalent_pick.h"
#include "granpack/stages/stages.h"

namespace granpack {

namespace {

/// What one trajectory row needs, summed over ranks (each value has one contributing rank).
struct Probe {
  Vec<3> s_grain = Vec<3>::Zero(), s_j = Vec<3>::Zero(); ///< scaled positions
  Vec<3> velocity = Vec<3>::Zero(), spin = Vec<3>::Zero();
  double mass = 0, inertia = 0;
  double n_ij = 0, t_ij = 0, n_ik = 0, t_ik = 0; ///< the grain's two contacts (0: open)
  double grain_contacts = 0;                     ///< contacts of the grain now
  double launch_contacts_closed = 0;             ///< contacts of the launch still in place
  double new_contacts = 0;                       ///< contacts not in the launch network
};

Probe probe(RunContext<3>& ctx, const MdEngine<3>& engine, const DivalentCandidate& c,
            const std::vector<ContactKey>& launch) {
  const auto& p = ctx.system.particles;
  const GlobalId gi = c.grain, gj = c.contact[0].neighbour, gk = c.contact[1].neighbour;
  double buf[26] = {};
  for (std::size_t i = 0; i < p.n_owned(); ++i) {
    if (p.id[i] == gi) {
      for (int a = 0; a < 3; ++a) {
        buf[a] = p.position[i][a];
        buf[6 + a] = p.velocity[i][a];
        buf[9 + a] = p.angular_velocity[i][a];
      }
      buf[12] = p.mass[i];
      buf[13] = p.inertia[i];
    }
    if (p.id[i] == gj)
      for (int a = 0; a < 3; ++a)
        buf[3 + a] = p.position[i][a];
  }
  engine.for_each_contact(
      [&](std::size_t i, std::size_t j, const Vec<3>&, const ContactState<3>& st) {
        const ContactKey key = ContactKey::of(p.id[i], p.id[j]);
        const bool in_launch = std::binary_search(launch.begin(), launch.end(), key);
        buf[in_launch ? 19 : 20] += 1;
        if (key.first != gi && key.second != gi)
          return;
        buf[18] += 1;
        const GlobalId other = key.first == gi ? key.second : key.first;
        if (other == gj)
          buf[14] = st.normal_force, buf[15] = st.tangential_force.norm();
        if (other == gk)
          buf[16] = st.normal_force, buf[17] = st.tangential_force.norm();
      });
  global_sum_in_place(ctx.world, buf);
  Probe r;
  r.s_grain = Vec<3>(buf[0], buf[1], buf[2]);
  r.s_j = Vec<3>(buf[3], buf[4], buf[5]);
  r.velocity = Vec<3>(buf[6], buf[7], buf[8]);
  r.spin = Vec<3>(buf[9], buf[10], buf[11]);
  r.mass = buf[12], r.inertia = buf[13];
  r.n_ij = buf[14], r.t_ij = buf[15], r.n_ik = buf[16], r.t_ik = buf[17];
  r.grain_contacts = buf[18];
  r.launch_contacts_closed = buf[19];
  r.new_contacts = buf[20];
  return r;
}

double grain_energy(const Probe& q) {
  return 0.5 * q.mass * q.velocity.squaredNorm() + 0.5 * q.inertia * q.spin.squaredNorm();
}

/// The picked candidate, or an InputError naming the deck, the stage and what is allowed.
const DivalentCandidate& picked(const RunContext<3>& ctx, const std::vector<DivalentCandidate>& c,
                                const DivalentLaunchStage& p) {
  const std::string where =
      ctx.deck->file + ": stage[" + std::to_string(ctx.stage_index) + "] (divalent_launch)";
  if (c.empty())
    throw InputError(where + ": the packing has no divalent grain (a backbone grain with exactly "
                             "two contacts carrying N > 1e-4 a^2 P); nothing to launch");
  if (p.pick >= std::int64_t(c.size()))
    throw InputError(where + ": pick = " + std::to_string(p.pick) + " but the packing has " +
                     std::to_string(c.size()) + " divalent grains (allowed: 0 to " +
                     std::to_string(c.size() - 1) + ")");
  return c[std::size_t(p.pick)];
}

void check_law(const RunContext<3>& ctx) {
  const std::string where =
      ctx.deck->file + ": stage[" + std::to_string(ctx.stage_index) + "] (divalent_launch)";
  const ContactLawParams& m = ctx.contact_law;
  if (!(m.friction > 0))
    throw InputError(where + ": friction = " + std::to_string(m.friction) +
                     ": a divalent grain needs friction (allowed: mu > 0)");
  if (m.cohesion_force > 0 || m.rolling_stiffness > 0)
    throw InputError(where + ": the free rolling of [AR] App. E needs a cohesionless law "
                             "without rolling resistance (allowed: cohesion_force = 0, "
                             "rolling_stiffness = 0)");
}

StageReport launch(RunContext<3>& ctx, const DivalentLaunchStage& p) {
  GRANPACK_CHECK(ctx.decomposition,
                 "stage " << ctx.stage_index << " (divalent_launch): there is no sample yet");
  check_law(ctx);
  const auto& sample = ctx.deck->sample;
  const double a = sample.diameter, P = p.control.pressure;
  MdSettings<3> s = deck_md_settings(ctx);
  s.dt = ctx.deck->numerics.time_step_fraction *
         contact_duration(ctx.contact_law, ctx.deck->material.density, sample, 3, P);
  s.stress_control = true;
  s.cell = cell_control_of(ctx, p.control);

  // [AR] App. E starts from the equilibrium at rest.
  auto& parts = ctx.system.particles;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    parts.velocity[i].setZero();
    parts.angular_velocity[i].setZero();
  }
  ctx.system.cell.rate.setZero();
  const std::vector<ContactKey> launch_keys = all_contact_keys(ctx);
  if (p.frozen_network)
    s.pair_allowed = [&launch_keys](GlobalId x, GlobalId y) {
      return std::binary_search(launch_keys.begin(), launch_keys.end(), ContactKey{x, y});
    };
  MdEngine<3> engine(ctx, make_contact_law<3>(ctx.contact_law), s);
  const std::vector<DivalentCandidate> candidates =
      divalent_candidates(ctx, engine, 1e-4 * a * a * P);
  const DivalentCandidate& c = picked(ctx, candidates, p);
  const auto vec = [](const double(&x)[3]) { return Vec<3>(x[0], x[1], x[2]); };
  Probe q = probe(ctx, engine, c, launch_keys);
  const DivalentFrame fr0 = divalent_frame(vec(c.contact[0].r), vec(c.contact[1].r));
  const double omega0 =
      divalent_omega0(q.mass, fr0.distance, c.contact[0].force, p.centrifugal_ratio);
  const DivalentLaunch l =
      divalent_launch(vec(c.contact[0].r), vec(c.contact[1].r), vec(c.contact[0].branch),
                      vec(c.contact[1].branch), omega0);
  for (std::size_t i = 0; i < parts.n_owned(); ++i)
    if (parts.id[i] == c.grain) {
      parts.velocity[i] = l.velocity;
      parts.angular_velocity[i] = l.angular_velocity;
    }
  q = probe(ctx, engine, c, launch_keys);
  const double e_launch = grain_energy(q);
  const double launch_contacts = q.launch_contacts_closed;
  const double period = 2 * std::numbers::pi / omega0;
  const std::int64_t steps =
      p.max_steps > 0 ? p.max_steps : std::int64_t(std::ceil(p.turns * period / s.dt));
  {
    char buf[400];
    std::snprintf(buf, sizeof buf,
                  "  grain %lld (pick %lld of %zu divalent), neighbours %lld %lld, |F| %.4g N = "
                  "%.3g a^2 P, D/a %.4f, omega0 %.4g rad/s (turn %.4g s = %lld steps of %.3g s), "
                  "%s network, %.0f contacts",
                  (long long)c.grain, (long long)p.pick, candidates.size(),
                  (long long)c.contact[0].neighbour, (long long)c.contact[1].neighbour,
                  c.contact[0].force, c.contact[0].force / (a * a * P), fr0.distance / a, omega0,
                  period, (long long)std::llround(period / s.dt), s.dt,
                  p.frozen_network ? "frozen" : "free", launch_contacts);
    ctx.log->info(buf);
  }

  std::ofstream csv;
  const bool writer = rank_of(ctx.world) == 0;
  if (writer) {
    csv.open(ctx.output_dir / p.trajectory);
    GRANPACK_CHECK(csv, "cannot write " << (ctx.output_dir / p.trajectory).string());
    csv << "step,t,x_over_D,y_over_D,angle,grain_kinetic_over_launch,kinetic_over_launch,"
           "N_ij_over_F,T_ij_over_F,N_ik_over_F,T_ik_over_F,grain_contacts,"
           "launch_contacts_closed,new_contacts,pressure_over_P\n";
  }
  const std::int64_t first_step = ctx.system.step;
  const double first_time = ctx.system.time;
  const double phi0 = ctx.solid_fraction();
  double angle = 0, last_raw = 0, max_energy = 0, min_closed = launch_contacts;
  double max_new = 0;
  bool collapsed = false;
  const auto record = [&] {
    q = probe(ctx, engine, c, launch_keys);
    const Vec<3> rel = ctx.system.cell.min_image(q.s_j, q.s_grain); // from j to the grain
    const double x = rel.dot(fr0.f) / fr0.distance, y = rel.dot(fr0.t) / fr0.distance;
    // The angle turned, unwrapped across -pi / pi.
    const double raw = std::atan2(y, x);
    double d = raw - last_raw;
    d -= 2 * std::numbers::pi * std::nearbyint(d / (2 * std::numbers::pi));
    angle += d, last_raw = raw;
    // Before the first step the engine's energy is the packing's at rest, without the launch.
    const double ek =
        ctx.system.step == first_step ? grain_energy(q) : engine.observables().kinetic_energy;
    max_energy = std::max(max_energy, ek);
    min_closed = std::min(min_closed, q.launch_contacts_closed);
    max_new = std::max(max_new, q.new_contacts);
    collapsed = collapsed || q.launch_contacts_closed < (1 - p.collapse_fraction) * launch_contacts;
    if (writer) {
      const double f = c.contact[0].force;
      char buf[400];
      std::snprintf(buf, sizeof buf,
                    "%lld,%.9g,%.7g,%.7g,%.7g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.0f,%.0f,%.0f,%.7g\n",
                    (long long)(ctx.system.step - first_step), ctx.system.time - first_time, x, y,
                    angle, grain_energy(q) / e_launch, ek / e_launch, q.n_ij / f, q.t_ij / f,
                    q.n_ik / f, q.t_ik / f, q.grain_contacts, q.launch_contacts_closed,
                    q.new_contacts, engine.observables().stress_elastic.trace() / (3 * P));
      csv << buf << std::flush;
    }
  };
  record();
  const std::int64_t log_every = ctx.deck->output.log_every;
  const auto stop = [&] {
    if (p.stop_on == "never")
      return false;
    return collapsed || (p.stop_on == "rearrangement" && max_energy > p.energy_factor * e_launch);
  };
  for (std::int64_t k = 1; k <= steps && !stop(); ++k) {
    engine.step();
    if (k % p.record_every == 0 || k == steps)
      record();
    if (k % log_every == 0) {
      char buf[240];
      std::snprintf(buf, sizeof buf,
                    "  step %10lld  turns %.3f  Ek/Ek0 %.3g  grain Ek/Ek0 %.3g  launch contacts "
                    "closed %.0f / %.0f  new %.0f",
                    (long long)k, angle / (2 * std::numbers::pi),
                    engine.observables().kinetic_energy / e_launch, grain_energy(q) / e_launch,
                    q.launch_contacts_closed, launch_contacts, q.new_contacts);
      ctx.log->progress(buf);
    }
  }
  const bool rearranged = !collapsed && max_energy > p.energy_factor * e_launch;
  // The free rolling has ended when the grain has (nearly) stopped or no longer touches exactly
  // its two neighbours (it met a third grain, or left one).
  const bool rolling_on =
      grain_energy(q) >= 1e-2 * e_launch && q.grain_contacts == 2 && q.n_ij > 0 && q.n_ik > 0;
  const bool arrested = !collapsed && !rearranged && !rolling_on;
  const char* outcome = collapsed    ? "collapsed"
                        : rearranged ? "rearranged"
                        : arrested   ? "arrested"
                                     : "rolling";
  StageReport r;
  r.steps = ctx.system.step - first_step;
  r.time = ctx.system.time - first_time;
  r.phi = ctx.solid_fraction();
  r.pressure = engine.observables().stress_elastic.trace() / 3;
  r.values = {
      {"grain", double(c.grain)},
      {"neighbour_j", double(c.contact[0].neighbour)},
      {"neighbour_k", double(c.contact[1].neighbour)},
      {"divalent_grains", double(candidates.size())},
      {"contact_force_over_a2P", c.contact[0].force / (a * a * P)},
      {"D_over_a", fr0.distance / a},
      {"omega0", omega0},
      {"centrifugal_over_force", q.mass * omega0 * omega0 * fr0.distance / c.contact[0].force},
      {"launch_energy", e_launch},
      {"frozen_network", p.frozen_network ? 1.0 : 0.0},
      {"turns_done", angle / (2 * std::numbers::pi)},
      {"max_kinetic_over_launch", max_energy / e_launch},
      {"final_grain_kinetic_over_launch", grain_energy(q) / e_launch},
      {"launch_contacts", launch_contacts},
      {"min_launch_contacts_closed", min_closed},
      {"max_new_contacts", max_new},
      {"phi_change", *r.phi - phi0},
      {"collapsed", collapsed ? 1.0 : 0.0},
      {"rearranged", rearranged ? 1.0 : 0.0},
      {"arrested", arrested ? 1.0 : 0.0},
      {"network_holds", collapsed ? 0.0 : 1.0}};
  ctx.stress_target = StressTarget{ctx.stage_index, p.control.stress, p.control.fixed, P};
  char buf[300];
  std::snprintf(buf, sizeof buf,
                "  %s: %.3f turns in %lld steps, max Ek/Ek0 %.3g, launch contacts closed at least "
                "%.0f / %.0f, new contacts at most %.0f, dphi %.3g",
                outcome, angle / (2 * std::numbers::pi), (long long)r.steps, max_energy / e_launch,
                min_closed, launch_contacts, max_new, *r.phi - phi0);
  ctx.log->info(buf);
  return r;
}

} // namespace

template <int dim> StageReport run_stage(RunContext<dim>& ctx, const DivalentLaunchStage& p) {
  if constexpr (dim == 3)
    return launch(ctx, p);
  else
    throw InputError(ctx.deck->file + ": stage[" + std::to_string(ctx.stage_index) +
                     "] (divalent_launch) is 3D only");
}

template StageReport run_stage<2>(RunContext<2>&, const DivalentLaunchStage&);
template StageReport run_stage<3>(RunContext<3>&, const DivalentLaunchStage&);

} // namespace granpack
