// `fix_rattlers` stage: treatment II of [AR] sec. III C. The force-carrying backbone is held
// at rest and every rattler is pushed onto it by a small force of fixed, random direction,
// with frictionless contacts (a rattler slides until its push lies in the cone of its contact
// normals: generically it rests on dim contacts), until each rattler is in equilibrium.
// Contacts between two backbone grains keep their state (their tangential forces are put back
// after the frictionless run), so the backbone's forces are unchanged.
//
// Checkpoints inside the stage (docs/long-jobs.md): the frame holds the rattlers found at the
// stage start (a global sorted id list: the backbone is not recomputed from a mid-stage state),
// the step counter and the last criteria values; the pushes are re-derived from the ids and
// the seed. The contacts between two frozen grains are given their stage-start state back
// before each such checkpoint is written, so the checkpoint's own contact data carry it (a
// frozen-frozen contact only acts on frozen grains, whose forces are discarded every step:
// its state during the run changes nothing else, and the end of the stage overwrites it).
#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>

#include "granpack/comm/allgather.h"
#include "granpack/comm/backbone.h"
#include "granpack/comm/halo.h"
#include "granpack/comm/reduce.h"
#include "granpack/contact/derived_constants.h"
#include "granpack/core/error.h"
#include "granpack/engine/checkpoint.h"
#include "granpack/engine/material_law.h"
#include "granpack/engine/md_engine.h"
#include "granpack/stages/stages.h"

namespace granpack {

namespace {

/// A direction drawn from the grain id and the seed: the same on every rank count.
template <int dim> Vec<dim> push_direction(GlobalId id, std::uint64_t seed) {
  std::mt19937_64 rng(seed * 0x9E3779B97F4A7C15ULL + static_cast<std::uint64_t>(id));
  std::normal_distribution<double> normal(0.0, 1.0);
  Vec<dim> u;
  do {
    for (int k = 0; k < dim; ++k)
      u[k] = normal(rng);
  } while (u.norm() < 1e-3);
  return u.normalized();
}

/// Ids of every rank's rattlers, sorted, on every rank.
std::vector<GlobalId> all_ids(MPI_Comm comm, const std::vector<GlobalId>& mine) {
  std::vector<GlobalId> all = allgather_concat(comm, mine);
  std::sort(all.begin(), all.end());
  return all;
}

} // namespace

template <int dim> StageReport run_stage(RunContext<dim>& ctx, const FixRattlersStage& f) {
  const double P = f.pressure ? *f.pressure : ctx.stress_target.pressure;
  GRANPACK_CHECK(ctx.decomposition && P > 0,
                 "stage " << ctx.stage_index << " (" << ctx.stage_name
                          << ") needs an equilibrated packing from a compress stage");
  const auto& sample = ctx.deck->sample;
  const double a = sample.diameter;
  const double force_scale = pressure_force(dim, a, P);
  const double push = f.force * force_scale;
  const int min_contacts = min_backbone_contacts(dim, ctx.contact_law.friction);

  MdSettings<dim> s = deck_md_settings(ctx);
  s.dt = ctx.deck->numerics.time_step_fraction *
         contact_duration(ctx.contact_law, ctx.deck->material.density, sample, dim, P);
  s.stress_control = false;

  // Restart inside this stage: the rattlers found when it began and the loop's counters.
  const nlohmann::json resume = ctx.take_resume_frame();
  const bool resuming = !resume.is_null();
  std::vector<GlobalId> rattlers;
  std::int64_t steps = 0;
  double worst = 0, ek = 0;
  if (resuming) {
    GRANPACK_CHECK(resume.value("stage", "") == "fix_rattlers",
                   "stage " << ctx.stage_index << " (" << ctx.stage_name
                            << "): the checkpoint's frame is of a '" << resume.value("stage", "?")
                            << "' stage, not of fix_rattlers");
    rattlers = resume.at("rattlers").get<std::vector<GlobalId>>();
    steps = resume.at("steps").get<std::int64_t>();
    worst = exact_double(resume.at("worst"));
    ek = exact_double(resume.at("ek"));
    GRANPACK_CHECK(std::is_sorted(rattlers.begin(), rattlers.end()) &&
                       std::adjacent_find(rattlers.begin(), rattlers.end()) == rattlers.end(),
                   "stage " << ctx.stage_index << " (" << ctx.stage_name
                            << "): the checkpoint's rattler ids are not sorted and unique");
  } else {
    // 1. The rattlers of the current state, by the rule of the compress stages.
    MdEngine<dim> engine(ctx, make_contact_law<dim>(ctx.contact_law), s);
    std::vector<CarryingContact> carrying;
    const double threshold = 1e-4 * force_scale; // [AR] force tolerance
    engine.for_each_contact(
        [&](std::size_t i, std::size_t j, const Vec<dim>&, const ContactState<dim>& st) {
          if (st.normal_force > threshold)
            carrying.push_back({i, j, st.normal_force});
        });
    const Backbone b = find_backbone(ctx.system.particles, engine.halo(), *ctx.decomposition,
                                     carrying, min_contacts);
    std::vector<GlobalId> mine;
    for (std::size_t i = 0; i < ctx.system.particles.n_owned(); ++i)
      if (b.rattler[i])
        mine.push_back(ctx.system.particles.id[i]);
    rattlers = all_ids(ctx.world, mine);
  }
  // The stage-start state of every contact (on a restart: the checkpoint's, whose contacts
  // between frozen grains hold it; the others are not used).
  const ContactStore<dim> saved = ctx.system.contacts;
  auto is_rattler = [&](GlobalId id) {
    return std::binary_search(rattlers.begin(), rattlers.end(), id);
  };
  // Contacts between two frozen grains get their stage-start state back.
  auto restore_backbone_contacts = [&] {
    for (std::size_t k = 0; k < ctx.system.contacts.size(); ++k) {
      const ContactKey& key = ctx.system.contacts.key(k);
      if (is_rattler(key.first) || is_rattler(key.second))
        continue;
      const auto old = saved.find(key);
      if (old >= 0)
        ctx.system.contacts.state(k) = saved.state(static_cast<std::size_t>(old));
    }
  };

  // 2. Frictionless MD of the rattlers alone, pushed by their random forces.
  ContactLawParams frictionless = ctx.contact_law;
  frictionless.friction = 0;
  s.mobile = &rattlers;
  // The pushes, drawn once per rattler (in the order of the sorted ids), not at every step.
  std::vector<Vec<dim>> pushes(rattlers.size());
  for (std::size_t k = 0; k < rattlers.size(); ++k)
    pushes[k] = push * push_direction<dim>(rattlers[k], f.seed);
  s.body_force = [&](GlobalId id) -> Vec<dim> {
    const auto it = std::lower_bound(rattlers.begin(), rattlers.end(), id);
    return pushes[static_cast<std::size_t>(it - rattlers.begin())];
  };
  // A checkpoint inside the loop is taken in the middle of engine.step(), before ++steps.
  // Its writer calls this provider before writing the grains and contacts (checkpoint.cpp):
  // the frozen grains' contacts are put back as the stage found them, in the continuing run
  // too, so that it and a restarted one go on from the same state.
  StageFrame<dim> frame(ctx, [&] {
    restore_backbone_contacts();
    return nlohmann::json{{"stage", "fix_rattlers"},
                          {"rattlers", rattlers},
                          {"steps", steps},
                          {"worst", exact(worst)},
                          {"ek", exact(ek)}};
  });
  // On a mid-step restart the engine's constructor completes the interrupted step.
  MdEngine<dim> engine(ctx, make_contact_law<dim>(frictionless), s);
  auto& p = ctx.system.particles;
  const double ek_limit = f.tolerance * f.tolerance * push * a;
  std::ostringstream head;
  head << "  " << rattlers.size() << " rattlers pushed by " << f.force
       << " a^2 P onto the frozen backbone (frictionless), dt " << s.dt << " s";
  if (resuming)
    head << "; resumed after " << steps << " steps of the stage";
  ctx.log->info(head.str());
  bool step_completed = resuming;
  while (true) {
    if (step_completed) {
      step_completed = false;
      ++steps;
    }
    if (steps % 50 == 0) {
      double local_f = 0, local_e = 0;
      for (std::size_t i = 0; i < p.n_owned(); ++i) {
        local_f = std::max(local_f, p.force[i].norm());
        local_e += 0.5 * p.mass[i] * p.velocity[i].squaredNorm();
      }
      worst = global_max(ctx.world, local_f) / push;
      ek = global_sum(ctx.world, local_e) / std::max<double>(1.0, double(rattlers.size()));
      if (steps > 0 && worst < f.tolerance && ek < ek_limit)
        break;
      if (steps % (50 * 400) == 0) {
        std::ostringstream os;
        os << "  step " << steps << ": max net force on a rattler / push " << worst
           << ", kinetic energy per rattler / (push a) " << ek / (push * a);
        ctx.log->progress(os.str());
      }
    }
    if (f.max_steps > 0 && steps >= f.max_steps)
      break;
    engine.step();
    step_completed = true;
  }
  const bool settled = worst < f.tolerance && ek < ek_limit;

  // 3. Backbone contacts get their frictional state back; the coordination of every grain
  //    (any contact carrying force) is treatment II's x_i.
  restore_backbone_contacts();
  std::vector<double> count(p.size(), 0.0);
  engine.for_each_contact(
      [&](std::size_t i, std::size_t j, const Vec<dim>&, const ContactState<dim>& st) {
        if (st.normal_force > 0)
          count[i] += 1, count[j] += 1;
      });
  engine.halo().reverse_values(count, *ctx.decomposition);
  constexpr int max_z = 13;
  std::vector<std::int64_t> hist(max_z + 1, 0);
  std::int64_t resting = 0;
  for (std::size_t i = 0; i < p.n_owned(); ++i) {
    const int z = std::min(max_z, static_cast<int>(std::lround(count[i])));
    ++hist[static_cast<std::size_t>(z)];
    if (is_rattler(p.id[i]) && z >= dim)
      ++resting;
  }
  global_sum_in_place(ctx.world, hist);
  resting = global_sum(ctx.world, resting);
  ctx.fixed_rattlers = rattlers; // /network/fixed_rattler of the files written from now on

  StageReport r;
  r.steps = steps;
  r.time = double(steps) * s.dt;
  r.equilibrated = settled;
  r.values.emplace_back("rattlers", double(rattlers.size()));
  r.values.emplace_back("rattlers_resting_on_dim_contacts", double(resting));
  const double n = static_cast<double>(sample.n);
  std::ostringstream os;
  os << "  " << (settled ? "settled" : "NOT settled (max_steps reached)") << " after " << steps
     << " steps; " << resting << " of " << rattlers.size() << " rattlers rest on >= " << dim
     << " contacts; x_i (II), %:";
  for (int z = 0; z <= max_z; ++z) {
    // Built by appends: GCC 12 warns (-Wrestrict, a false positive) on "x" + to_string(z) + "_II".
    std::string key = "x";
    key += std::to_string(z);
    key += "_II";
    r.values.emplace_back(key, double(hist[std::size_t(z)]) / n);
    if (hist[std::size_t(z)])
      os << " " << z << ":" << 100.0 * double(hist[std::size_t(z)]) / n;
  }
  ctx.log->info(os.str());
  return r;
}

template StageReport run_stage<2>(RunContext<2>&, const FixRattlersStage&);
template StageReport run_stage<3>(RunContext<3>&, const FixRattlersStage&);

} // namespace granpack
