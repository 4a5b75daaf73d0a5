#include "granpack/engine/md_engine.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>

#include "granpack/comm/collective_error.h"
#include "granpack/comm/communicator.h"
#include "granpack/comm/fault_injection.h"
#include "granpack/comm/migration.h"
#include "granpack/comm/rebalance.h"
#include "granpack/comm/reduce.h"
#include "granpack/core/error.h"
#include "granpack/dynamics/integrator.h"
#include "granpack/engine/state_file.h"
#include "granpack/engine/stop_signals.h"
#include "granpack/engine/trajectory.h"

namespace granpack {

template <int dim>
MdEngine<dim>::MdEngine(RunContext<dim>& ctx, const ContactLaw<dim>& law,
                        const MdSettings<dim>& settings)
    : ctx_(ctx), law_(law), settings_(settings), halo_(settings.halo) {
  GRANPACK_CHECK(ctx.decomposition, "the MD engine needs a sample (a lattice or random stage)");
  GRANPACK_CHECK(settings.dt > 0, "time step must be positive");
  double r = 0;
  for (std::size_t i = 0; i < ctx.system.particles.n_owned(); ++i)
    r = std::max(r, ctx.system.particles.radius[i]);
  max_radius_ = global_max(ctx.world, r);
  n_grains_ = global_sum(ctx.world, static_cast<std::int64_t>(ctx.system.particles.n_owned()));
  rebuild();
  if (ctx.resume_mid_step) {
    // Restart inside a stage: the checkpoint was taken in the middle of a step, right after
    // a canonical rebuild like the one above; finish that step as the interrupted run did.
    ctx.resume_mid_step = false;
    finish_step();
  } else {
    forces_and_observables();
  }
  tallied_seconds_ = timers_.total(); // the set-up is no step
}

template <int dim> void MdEngine<dim>::rebuild() {
  auto& sys = ctx_.system;
  auto& d = *ctx_.decomposition;
  // Ghost layer: every grain that can come within reach of ours before the next rebuild.
  const double cutoff = 2 * max_radius_ + law_.interaction_range() + settings_.skin;
  const Vec<dim> width = Vec<dim>::Constant(cutoff).cwiseQuotient(sys.cell.length);
  const bool balancing = settings_.load_balance_threshold > 0 && d.size() > 1;
  {
    ScopedPhase t(timers_.comm);
    sys.particles.clear_ghosts();
    migrate(sys, d);
    // Moved planes that the shrinking cell made narrower than the ghost layer: new ones (by
    // grain count: the list that gives the work is not built yet) before the halo needs them.
    if (balancing && planes_too_narrow(d, width) && rebalance(d, sys.particles, {}, width)) {
      migrate(sys, d);
      ++rebalances_;
    }
  }
  build_halo_and_list(cutoff);
  // Load balancing by the work of the new lists, decided from the positions, the cell and the
  // planes alone, so that a restart (whose checkpoint holds the planes) repeats every decision.
  if (balancing) {
    const std::vector<std::int64_t> work = grain_work();
    std::int64_t load = 0;
    for (const std::int64_t w : work)
      load += w;
    if (load_imbalance(ctx_.world, load) > settings_.load_balance_threshold &&
        rebalance(d, sys.particles, work, width)) {
      {
        ScopedPhase t(timers_.comm);
        sys.particles.clear_ghosts();
        migrate(sys, d);
      }
      build_halo_and_list(cutoff);
      ++rebalances_;
    }
  }
  ++rebuilds_;
}

template <int dim> void MdEngine<dim>::build_halo_and_list(double cutoff) {
  auto& sys = ctx_.system;
  {
    ScopedPhase t(timers_.comm);
    // Grains in a canonical spatial order (bins of about the list's cutoff, then id): the
    // pair loop then finds a grain's neighbours close in memory (docs/performance.md), and
    // every later sum (forces, virial, reductions) follows an order that depends on the
    // positions and ids only, which a restarted run reproduces from its checkpoint.
    std::array<std::size_t, dim> bins;
    for (int a = 0; a < dim; ++a)
      bins[a] = static_cast<std::size_t>(std::max(1.0, std::floor(sys.cell.length[a] / cutoff)));
    sys.particles.sort_owned_spatially(bins);
    halo_.borders(sys.particles, *ctx_.decomposition,
                  Vec<dim>::Constant(cutoff).cwiseQuotient(sys.cell.length));
  }
  ScopedPhase t(timers_.neighbor);
  collectively(ctx_.world, [&] {
    list_.build(sys.particles, sys.cell, NeighborParams{settings_.skin, law_.interaction_range()});
  });
  if (settings_.pair_allowed) {
    const auto& id = sys.particles.id;
    list_.retain_pairs([&](std::size_t i, std::size_t j) {
      return settings_.pair_allowed(std::min(id[i], id[j]), std::max(id[i], id[j]));
    });
  }
  loop_.bind(sys.particles, list_, sys.contacts);
}

template <int dim> std::vector<std::int64_t> MdEngine<dim>::grain_work() {
  // 2 per grain and 1 per listed pair it belongs to: a grain costs about what a pair costs
  // (integration and list building against one force evaluation). The pairs a rank lists with
  // a ghost reach the ghost's owner by reverse communication, so a grain's count is the same on
  // any decomposition (the lists hold every pair within the cutoff once).
  const auto& p = ctx_.system.particles;
  std::vector<double> ends(p.size(), 0.0);
  for (std::size_t i = 0; i < list_.n_owned(); ++i) {
    ends[i] += static_cast<double>(list_.end(i) - list_.begin(i));
    for (const std::uint32_t* j = list_.begin(i); j != list_.end(i); ++j)
      ends[*j] += 1.0;
  }
  {
    ScopedPhase t(timers_.comm);
    halo_.reverse_values(ends, *ctx_.decomposition);
  }
  std::vector<std::int64_t> work(p.n_owned());
  for (std::size_t i = 0; i < p.n_owned(); ++i)
    work[i] = 2 + static_cast<std::int64_t>(ends[i]);
  return work;
}

template <int dim> void MdEngine<dim>::forces_and_observables() {
  auto& sys = ctx_.system;
  ForceSums<dim> sums;
  {
    ForcePhaseTimer t(timers_);
    sums = loop_.compute(sys, list_, law_, settings_.dt);
  }
  {
    ScopedPhase t(timers_.comm);
    halo_.reverse(sys.particles, *ctx_.decomposition);
  }
  if (settings_.mobile)
    hold_and_push();

  // One all-reduce for every global sum of the step.
  constexpr int nt = dim * dim;
  double local[2 * nt + 2], global[2 * nt + 2];
  Tensor<dim> kinetic = Tensor<dim>::Zero();
  const auto& p = sys.particles;
  double ek = 0, v2max = 0;
  for (std::size_t i = 0; i < p.n_owned(); ++i) {
    kinetic.noalias() += p.mass[i] * p.velocity[i] * p.velocity[i].transpose();
    ek += 0.5 * p.inertia[i] * p.angular_velocity[i].squaredNorm();
    v2max = std::max(v2max, p.velocity[i].squaredNorm());
  }
  // The largest overlap and the largest displacement in a step (|v| dt with the velocity
  // that drifted the grains), for one all-reduce below. Computed here, before the calls into
  // MPI: a value live across a call is kept in memory for its whole life (every xmm register
  // is caller-saved), and the loop's running maximum then went through a store and a load
  // each iteration, two thirds of this loop's time (perf, 1400 disks).
  double mx[2] = {sums.max_overlap, std::sqrt(v2max) * settings_.dt};
  ek += 0.5 * kinetic.trace();
  Eigen::Map<Tensor<dim>> total_part(local), elastic_part(local + nt);
  total_part = sums.virial + kinetic;
  elastic_part = sums.virial_elastic;
  local[2 * nt] = ek;
  local[2 * nt + 1] = static_cast<double>(sums.interacting);
  ScopedPhase t(timers_.comm);
  global_sum(ctx_.world, local, global);
  const double volume = sys.cell.volume();
  obs_.stress = Eigen::Map<Tensor<dim>>(global) / volume;
  obs_.stress_elastic = Eigen::Map<Tensor<dim>>(global + nt) / volume;
  obs_.kinetic_energy = global[2 * nt];
  obs_.contacts = static_cast<std::int64_t>(global[2 * nt + 1]);
  global_max_in_place(ctx_.world, mx);
  obs_.max_overlap = mx[0];
  obs_.max_step_displacement = mx[1];
}

template <int dim> void MdEngine<dim>::hold_and_push() {
  auto& p = ctx_.system.particles;
  const auto& mobile = *settings_.mobile;
  for (std::size_t i = 0; i < p.n_owned(); ++i) {
    if (std::binary_search(mobile.begin(), mobile.end(), p.id[i])) {
      if (settings_.body_force)
        p.force[i] += settings_.body_force(p.id[i]);
    } else {
      p.force[i].setZero();
      p.torque[i].setZero();
      p.velocity[i].setZero();
      p.angular_velocity[i].setZero();
    }
  }
}

template <int dim> void MdEngine<dim>::step() {
  auto& sys = ctx_.system;
  auto& p = sys.particles;
  const double dt = settings_.dt;
  {
    ScopedPhase t(timers_.integrate);
    kick(p, 0.5 * dt);
    if (settings_.stress_control)
      settings_.cell.kick(sys.cell, obs_.stress.diagonal(), 0.5 * dt);
    drift(p, sys.cell, dt);
    if (settings_.stress_control)
      CellControl<dim>::drift(sys.cell, dt);
  }

  // One all-reduce decides for every rank: rebuild the lists, checkpoint, stop.
  int bits = 0;
  {
    ScopedPhase t(timers_.neighbor);
    bits = list_.needs_rebuild(p, sys.cell) ? kRequestRebuild : 0;
  }
  if (ctx_.checkpointer)
    bits |= ctx_.checkpointer->local_request(sys.step + 1);
  {
    ScopedPhase t(timers_.comm);
    fault_point(FaultPoint::kCollective);
    bits = global_bit_or(ctx_.world, bits);
  }
  // A checkpoint inside a stage needs the stage's state (its frame); stages without one
  // checkpoint at their end (run_deck). It waits for a step that rebuilds anyway (take_now).
  if (!ctx_.frames.empty() && ctx_.checkpointer && ctx_.checkpointer->take_now(bits)) {
    rebuild();
    ctx_.checkpointer->write(ctx_, true);
    ctx_.checkpointer->stop_if_requested(bits, sys.step);
  } else if (bits & kRequestRebuild) {
    rebuild();
  } else {
    ScopedPhase t(timers_.comm);
    halo_.forward(p, *ctx_.decomposition);
  }
  finish_step();
}

template <int dim> void MdEngine<dim>::finish_step() {
  auto& sys = ctx_.system;
  const double dt = settings_.dt;
  forces_and_observables();
  check_sanity();
  {
    ScopedPhase t(timers_.integrate);
    kick(sys.particles, 0.5 * dt);
    if (settings_.stress_control)
      settings_.cell.kick(sys.cell, obs_.stress.diagonal(), 0.5 * dt);
  }
  const double time_before = sys.time;
  sys.time += dt;
  ++sys.step;
  tally_step();
  if (trajectory_due(ctx_, time_before))
    write_snapshot(ctx_);
  fault_point(FaultPoint::kStep, sys.step);
  if (fault_point(FaultPoint::kHold, sys.step))
    wait_for_stop_signal();
}

template <int dim> void MdEngine<dim>::tally_step() {
  const double total = timers_.total();
  const bool dense =
      static_cast<double>(obs_.contacts) >= kDenseContactsPerGrain * static_cast<double>(n_grains_);
  StepClassTally& c = dense ? timers_.dense : timers_.loose;
  ++c.steps;
  c.particle_steps += n_grains_;
  c.seconds += total - tallied_seconds_;
  tallied_seconds_ = total;
}

template <int dim> void MdEngine<dim>::check_sanity() {
  // Global values first (identical on every rank, so every rank decides alike); the search
  // for the culprit grain runs only when something is wrong.
  const bool finite = obs_.stress.allFinite() && std::isfinite(obs_.kinetic_energy) &&
                      std::isfinite(obs_.max_step_displacement);
  const bool overlap_ok = obs_.max_overlap <= settings_.max_overlap;
  const bool moves_ok =
      obs_.max_step_displacement <= settings_.max_step_displacement * settings_.skin;
  if (finite && overlap_ok && moves_ok)
    return;
  const std::string at = "step " + std::to_string(ctx_.system.step) + ": ";
  CollectiveError err;
  const auto& p = ctx_.system.particles;
  for (std::size_t i = 0; i < p.n_owned() && !finite; ++i) {
    if (!p.position[i].allFinite() || !p.velocity[i].allFinite() || !p.force[i].allFinite()) {
      err.record(at + "grain " + std::to_string(p.id[i]) +
                 " has a non-finite position, velocity or force (likely fix: a smaller "
                 "[numerics] time_step_fraction)");
      break;
    }
  }
  if (!finite && !err.has_local() && ctx_.world != MPI_COMM_NULL) {
    // Only the global sums are not finite: say so once, from rank 0.
    const int rank = rank_of(ctx_.world);
    if (rank == 0)
      err.record(at + "the stress or kinetic energy is not finite (likely fix: a smaller "
                      "[numerics] time_step_fraction)");
  }
  if (finite && !overlap_ok) {
    // The pair with the largest overlap, on the rank that computed it.
    double worst = -1;
    std::string pair;
    loop_.for_each_contact(
        ctx_.system, list_,
        [&](std::size_t i, std::size_t j, const Vec<dim>&, const ContactState<dim>&) {
          const Vec<dim> r = ctx_.system.cell.length.cwiseProduct(p.position[j] - p.position[i]);
          const double h =
              (p.radius[i] + p.radius[j] - r.norm()) / std::min(p.radius[i], p.radius[j]);
          if (h > worst)
            worst = h, pair = std::to_string(p.id[i]) + " and " + std::to_string(p.id[j]);
        });
    if (worst >= obs_.max_overlap * (1 - 1e-9)) {
      std::ostringstream os;
      os << at << "the overlap of grains " << pair << " reached " << worst
         << " of the smaller radius (limit " << settings_.max_overlap
         << ", [numerics] max_overlap): the contacts are too soft for the pressure or the time "
            "step too large (likely fix: a smaller [numerics] time_step_fraction, stiffer "
            "material or a cap inertia_max on the compression; soft contacts on purpose, as "
            "[GRC]'s kappa = 1e2: raise max_overlap)";
      err.record(os.str());
    }
  }
  if (finite && overlap_ok && !moves_ok) {
    for (std::size_t i = 0; i < p.n_owned(); ++i) {
      if (p.velocity[i].norm() * settings_.dt >= obs_.max_step_displacement * (1 - 1e-12)) {
        std::ostringstream os;
        os << at << "grain " << p.id[i] << " moved " << obs_.max_step_displacement
           << " m in one step, more than " << settings_.max_step_displacement * settings_.skin
           << " m (the Verlet skin): the packing is blowing up, or the skin is too thin (likely "
              "fix: a smaller [numerics] "
              "time_step_fraction, a cap inertia_max on the compression, or a larger skin)";
        err.record(os.str());
        break;
      }
    }
  }
  write_postmortem();
  err.raise_if_any(ctx_.world);
  // Every check failed globally, so some rank must have found a culprit; if rounding hid
  // it, still never continue with a bad state.
  throw Error(at +
              "the run went bad (non-finite values, overlap or displacement beyond the limits)");
}

template <int dim> void MdEngine<dim>::write_postmortem() {
  if (!ctx_.deck || ctx_.output_dir.empty())
    return;
  const auto file = ctx_.output_dir / "postmortem.h5";
  try {
    write_state(ctx_, file);
    ctx_.log->warn("the state of the failing step was written to " + file.string());
  } catch (const Error& e) {
    ctx_.log->warn("could not write the post-mortem snapshot " + file.string() + ": " + e.what());
  }
}

template <int dim>
EquilibriumMeasure MdEngine<dim>::measure(const EquilibriumScales& scales, bool with_moment) {
  auto& sys = ctx_.system;
  std::vector<Vec<dim>> fel;
  std::vector<RotVec<dim>> gel;
  loop_.elastic_forces(sys, list_, law_, fel, with_moment ? &gel : nullptr);
  // Largest norm over owned grains of a per-grain vector whose ghost parts still have to be
  // added to their owners.
  auto max_norm = [&](const auto& vecs, int components) {
    std::vector<double> comp(vecs.size());
    std::vector<double> norm2(sys.particles.n_owned(), 0.0);
    for (int a = 0; a < components; ++a) {
      for (std::size_t i = 0; i < vecs.size(); ++i)
        comp[i] = vecs[i][a];
      halo_.reverse_values(comp, *ctx_.decomposition);
      for (std::size_t i = 0; i < norm2.size(); ++i)
        norm2[i] += comp[i] * comp[i];
    }
    double m2 = 0;
    for (double v2 : norm2)
      m2 = std::max(m2, v2);
    return std::sqrt(global_max(ctx_.world, m2));
  };
  EquilibriumMeasure m;
  m.force = max_norm(fel, dim) / scales.force;
  if (with_moment)
    m.moment = max_norm(gel, rot_dim<dim>) / scales.moment;
  const double stress_scale = scales.stress, energy_scale = scales.energy;
  double err = 0;
  for (int a = 0; a < dim; ++a)
    if (!settings_.cell.fixed[a])
      err = std::max(err, std::abs(obs_.stress_elastic(a, a) - settings_.cell.target[a]));
  m.stress = err / stress_scale;
  // Kinetic energy of every grain, translation and spin, as [AR] sec. III and [GRC] II D count
  // it. A caged rattler spinning freely keeps its energy (nothing damps a grain without
  // contacts), so decks that meet the criterion through such grains quench (quench_interval).
  const auto& p = sys.particles;
  double ek = 0;
  for (std::size_t i = 0; i < p.n_owned(); ++i)
    ek += 0.5 * p.mass[i] * p.velocity[i].squaredNorm() +
          0.5 * p.inertia[i] * p.angular_velocity[i].squaredNorm();
  const auto n = global_sum(ctx_.world, static_cast<std::int64_t>(p.n_owned()));
  m.kinetic = global_sum(ctx_.world, ek) / static_cast<double>(n) / energy_scale;
  return m;
}

template class MdEngine<2>;
template class MdEngine<3>;

} // namespace granpack
