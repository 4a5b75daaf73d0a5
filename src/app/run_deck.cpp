#include "granpack/app/run_deck.h"

#include <array>
#include <chrono>
#include <cstdio>
#include <optional>
#include <sstream>

#include "granpack/app/build_info.h"
#include "granpack/comm/barrier.h"
#include "granpack/comm/broadcast.h"
#include "granpack/comm/collective_error.h"
#include "granpack/comm/communicator.h"
#include "granpack/comm/rebalance.h"
#include "granpack/comm/reduce.h"
#include "granpack/comm/shared_window.h"
#include "granpack/core/error.h"
#include "granpack/engine/checkpoint.h"
#include "granpack/engine/stop_signals.h"
#include "granpack/engine/trajectory.h"
#include "granpack/io/deck.h"
#include "granpack/io/deck_seed.h"
#include "granpack/io/hdf5_store.h"
#include "granpack/io/output_lock.h"
#include "granpack/stages/stages.h"

namespace granpack {

/// Reads the deck on rank 0 and broadcasts its text, so all ranks validate the same bytes
/// and throw the same InputError together; with `seed`, the deck reseeded (deck_seed.h).
Deck load_deck_collectively(MPI_Comm world, const std::filesystem::path& path,
                            std::optional<std::uint64_t> seed) {
  const int rank = rank_of(world);
  std::string text;
  int ok = 1;
  if (rank == 0) {
    try {
      text = read_deck_text(path);
    } catch (const InputError& e) {
      text = e.what();
      ok = 0;
    }
  }
  ok = broadcast_value(world, ok);
  broadcast_string(world, text);
  if (!ok)
    throw InputError(text); // on every rank, same message
  if (seed)
    text = reseeded_deck_text(text, path.string(), *seed);
  return parse_deck(text, path.string());
}

namespace {

std::string fmt_opt(const std::optional<double>& v) {
  if (!v)
    return "-";
  std::ostringstream os;
  os.precision(6);
  os << *v;
  return os.str();
}

/// A stage's timers over the ranks (means; maxima for the load balance).
struct StageTiming {
  std::optional<PhaseSeconds> phases; ///< none when the stage ran no MD engine
  WallSplit split;                    ///< `other` is set once the stage's wall time is known
  std::optional<StepClasses> classes; ///< with phases
};

/// Collective: one all-reduce of the sums and one of the maxima, at the stage's end.
StageTiming stage_timing_over_ranks(MPI_Comm world, const StageTimers& st) {
  const auto size = static_cast<double>(size_of(world));
  const StepTimers& t = st.md;
  const double forces_cpu = t.forces_cpu_estimate();
  std::array sum{t.forces, t.neighbor,      t.comm,          t.integrate,    forces_cpu,
                 st.io,    st.event_driven, t.dense.seconds, t.loose.seconds};
  std::array max{t.forces, forces_cpu};
  global_sum_in_place(world, sum);
  global_max_in_place(world, max);
  for (double& x : sum)
    x /= size;
  StageTiming r;
  r.split = {sum[0], sum[1], sum[2], sum[3], sum[5], sum[6], 0};
  if (sum[0] + sum[1] + sum[2] + sum[3] <= 0)
    return r;
  PhaseSeconds p;
  p.forces = sum[0], p.neighbor = sum[1], p.comm = sum[2], p.integrate = sum[3];
  p.forces_cpu = sum[4];
  p.forces_slowest = max[0], p.forces_cpu_slowest = max[1];
  r.phases = p;
  // Steps and grain-steps are the same on every rank: the class of a step comes from the
  // step's global contact count.
  r.classes = StepClasses{kDenseContactsPerGrain,
                          {t.dense.steps, t.dense.particle_steps, sum[7]},
                          {t.loose.steps, t.loose.particle_steps, sum[8]}};
  return r;
}

std::string fmt_g(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

/// The stage's wall time by part: the parts that took any time, and the rest.
std::string split_line(const WallSplit& w) {
  std::string line = "  time (s, mean over ranks):";
  const std::pair<const char*, double> parts[] = {{"forces", w.forces},
                                                  {"neighbours", w.neighbor},
                                                  {"communication", w.comm},
                                                  {"integration", w.integrate},
                                                  {"I/O", w.io},
                                                  {"event-driven", w.event_driven}};
  for (const auto& [name, seconds] : parts)
    if (seconds > 0)
      line += std::string(" ") + name + " " + fmt_g(seconds) + ",";
  return line + " other " + fmt_g(w.other);
}

/// The MD steps by class with their rates, and the load balance of the force work.
std::string classes_line(const StepClasses& c, const PhaseSeconds& p) {
  auto one = [](const char* name, const StepClass& k) {
    const auto rate = k.rate();
    return std::string(name) + " " + std::to_string(k.steps) +
           (rate ? " (" + fmt_g(*rate) + " particle-steps/s)" : std::string());
  };
  char imbalance[80];
  std::snprintf(imbalance, sizeof imbalance, "; force work of the slowest rank / mean %.3f",
                p.force_imbalance());
  return "  MD steps: " + one("dense", c.dense) + ", " + one("loose", c.loose) +
         " (dense: contacts per grain >= " + fmt_g(c.threshold) + ")" + imbalance;
}

/// Restores the state a checkpoint holds: grains, contacts, cell, time and step, the domain
/// grid (the same one on the same rank count), the RunContext's contact law and stress target
/// (its /parameters) and the frames of the stages in progress.
template <int dim>
void restore(RunContext<dim>& ctx, const std::filesystem::path& file, const RunState& state) {
  Configuration<dim> c = read_configuration<dim>(ctx.world, file);
  if (c.meta.parameters) {
    ctx.contact_law = c.meta.parameters->contact_law;
    ctx.stress_target = c.meta.parameters->stress_target;
  } else if (state.legacy) {
    const StateParameters p = legacy_parameters(state, *ctx.deck);
    ctx.contact_law = p.contact_law;
    ctx.stress_target = p.stress_target;
    ctx.log->info("  " + file.string() +
                  " was written before checkpoints held /parameters: the "
                  "contact law is the deck's [material] with the changes its run state records");
  } else {
    throw InputError(file.string() + ": a checkpoint of run_state format 2 without the group "
                                     "/parameters (corrupt file)");
  }
  ctx.system.time = c.meta.time;
  ctx.system.step = c.meta.step;
  const int size = size_of(ctx.world);
  std::array<int, dim> grid{};
  const bool same_grid = size == state.ranks && state.grid.size() == dim;
  if (same_grid)
    std::copy(state.grid.begin(), state.grid.end(), grid.begin());
  const std::array<int, dim>* chosen = same_grid ? &grid : nullptr;
  // The cut planes come with the grid (on another rank count the grid is new and uniform).
  std::array<std::vector<double>, dim> cuts;
  const bool with_cuts = same_grid && state.cuts.size() == dim;
  if (with_cuts)
    std::copy(state.cuts.begin(), state.cuts.end(), cuts.begin());
  adopt_configuration<dim>(ctx, std::move(c), chosen, with_cuts ? &cuts : nullptr);
  ctx.resume.assign(state.frames.begin(), state.frames.end());
  ctx.fixed_rattlers = state.fixed_rattlers;
  ctx.resume_mid_step = state.mid_stage;
}

template <int dim>
void run_stages(MPI_Comm world, const Deck& deck, Log& log, const std::filesystem::path& out,
                RunReport& report, Checkpointer& checkpointer, const RunOptions& options,
                const std::optional<RunState>& state) {
  RunContext<dim> ctx;
  ctx.world = world;
  ctx.deck = &deck;
  ctx.contact_law = contact_law_params(deck.material);
  ctx.log = &log;
  ctx.output_dir = out;
  ctx.checkpointer = &checkpointer;
  checkpointer.completed = &report.stages;
  std::size_t first = 0;
  if (state) {
    restore(ctx, *options.restart, *state);
    report.stages = state->completed;
    checkpointer.earlier_wall_seconds = state->wall_seconds;
    first = static_cast<std::size_t>(state->stage_index);
    log.info("restart from " + options.restart->string() + " at step " +
             std::to_string(ctx.system.step) + ": " +
             (first < deck.stages.size()
                  ? (state->mid_stage ? "inside" : "at the start of") + std::string(" stage ") +
                        std::to_string(first) + " '" + deck.stages[first].name + "'"
                  : std::string("every stage is done")));
  }
  start_trajectory(ctx, state.has_value());
  for (std::size_t index = first; index < deck.stages.size(); ++index) {
    const auto& st = deck.stages[index];
    ctx.stage_index = st.index;
    ctx.stage_name = st.name;
    log.info("stage " + std::to_string(st.index) + " '" + st.name + "' (" + st.kind + ")");
    auto t0 = std::chrono::steady_clock::now();
    ctx.stage_timers = {};
    ctx.stage_rebalances = 0;
    // The rattlers fix_rattlers placed stay flagged until a stage moves the grains again (a
    // restart inside fix_rattlers finds the list empty: it is set at the stage's end; a read
    // stage sets it from its file).
    if (st.kind != "set" && st.kind != "write")
      ctx.fixed_rattlers.clear();
    // No rank starts a timed part before rank 0 started the stage's clock, and every part ends
    // before the all-reduce of the timers: the parts (means over the ranks) fit in wall_seconds.
    barrier(world);
    // The runner of the stage's kind (stages/stages.h; the registry: io/stage_params.h).
    StageReport r = std::visit([&](const auto& p) { return run_stage(ctx, p); }, st.params);
    // Before the checkpoint between stages: a restart from it keeps this snapshot.
    stage_end_snapshot(ctx);
    const StageTiming timing = stage_timing_over_ranks(world, ctx.stage_timers);
    r.phase_seconds = timing.phases;
    r.md_classes = timing.classes;
    GRANPACK_CHECK(ctx.resume.empty() && !ctx.resume_mid_step,
                   "stage " << st.index << " did not consume the checkpoint's resume state");
    r.name = st.name;
    r.kind = st.kind;
    if (!r.phi && ctx.decomposition)
      r.phi = ctx.solid_fraction();
    // set and write leave the packing as it was: its network metrics carry over.
    if ((st.kind == "set" || st.kind == "write") && !report.stages.empty())
      r.copy_state_metrics(report.stages.back());
    r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    r.wall_split = timing.split;
    r.wall_split->other = r.wall_seconds - r.wall_split->listed();
    report.stages.push_back(r);
    log.info(split_line(*r.wall_split));
    if (r.phase_seconds && r.md_classes)
      log.info(classes_line(*r.md_classes, *r.phase_seconds));
    if (deck.numerics.load_balance && ctx.decomposition && ctx.decomposition->size() > 1) {
      char buf[200];
      std::snprintf(buf, sizeof buf,
                    "  load balance: cut planes moved at %lld rebuilds; grains on the fullest "
                    "rank / mean now %.3f",
                    static_cast<long long>(ctx.stage_rebalances),
                    grain_imbalance(world, ctx.system.particles.n_owned()));
      log.info(buf);
    }
    log.info("  done: phi " + fmt_opt(r.phi) + ", steps " + std::to_string(r.steps) + ", wall " +
             fmt_opt(r.wall_seconds) + " s");
    // Between stages: a checkpoint (cheap next to a stage), and the place where a stage
    // without checkpoints inside honours a stop signal, as does an event-driven stage for a
    // signal during its last piece.
    if (index + 1 < deck.stages.size() && ctx.decomposition && checkpointer.policy().enabled()) {
      const int bits = checkpointer.global_request(ctx.system.step);
      checkpointer.write(ctx, false);
      checkpointer.stop_if_requested(bits, ctx.system.step);
    }
  }
  GRANPACK_CHECK(ctx.decomposition, "the deck never builds a sample (no lattice/random stage)");
  write_state(ctx, out / "final.h5");
  report.final_file = "final.h5";
  log.info("wrote " + (out / "final.h5").string());
}

} // namespace

int run_deck(MPI_Comm world, const RunOptions& options) {
  auto t0 = std::chrono::steady_clock::now();
  const int rank = rank_of(world), size = size_of(world);

  // 1. Validate everything before touching the output directory.
  Deck deck = load_deck_collectively(world, options.deck, options.seed);
  std::optional<RunState> state;
  if (options.restart) {
    const std::string file = options.restart->string();
    const FileMeta meta = read_file_meta(world, *options.restart);
    if (meta.kind != "checkpoint" || meta.run_state.empty())
      throw InputError(file + " is a " + meta.kind +
                       " file, not a checkpoint: --restart takes the DIR/checkpoint.h5 of an "
                       "interrupted run (a configuration can start a deck with a read stage)");
    if (meta.dimension != deck.sample.dimension)
      throw InputError(file + " holds a " + std::to_string(meta.dimension) + "D run; the deck is " +
                       std::to_string(deck.sample.dimension) + "D");
    state = parse_run_state(meta.run_state, file);
    const Deck original = parse_deck(meta.deck_text, file + ":/deck");
    check_restart_deck(original, deck, *state, options.allow_deck_change, file);
    // A checkpoint that contradicts its own deck was damaged or edited: refuse it before any
    // grain is read, rather than run something else than the deck says.
    const auto n_stages = static_cast<int>(original.stages.size());
    if (state->stage_index > n_stages || (state->mid_stage && state->stage_index == n_stages))
      throw InputError(file + ": /run_state stage_index " + std::to_string(state->stage_index) +
                       (state->mid_stage ? " (inside the stage)" : "") +
                       " is past the end of the deck the checkpoint was written with (" +
                       std::to_string(n_stages) + " stages): a damaged checkpoint");
    if (meta.n_particles != deck.sample.n)
      throw InputError(file + ": holds " + std::to_string(meta.n_particles) +
                       " grains, but its deck's [sample] n = " + std::to_string(deck.sample.n) +
                       ": a damaged checkpoint");
  }

  std::filesystem::path out = options.output_dir;
  if (out.empty())
    out = std::filesystem::path("out") / options.deck.stem();
  collectively(world, [&] {
    if (rank == 0) {
      std::error_code ec;
      std::filesystem::create_directories(out, ec);
      if (ec)
        throw InputError("cannot create the output directory " + out.string() + ": " +
                         ec.message());
    }
  });

  // One run per directory: refused here, before log.txt is opened (and truncated).
  OutputLock lock;
  collectively(world, [&] {
    if (rank == 0)
      lock = OutputLock(out);
  });

  Log log(rank == 0, options.quiet || deck.output.quiet);
  log.set_terminal_prefix(options.terminal_prefix);
  collectively(world, [&] { log.open_file((out / "log.txt").string(), state.has_value()); });
  log.info(build_description() + ": " + deck.file + " -> " + out.string() + " on " +
           std::to_string(size) + " rank(s), dimension " + std::to_string(deck.sample.dimension) +
           ", n = " + std::to_string(deck.sample.n));
  if (!lock.warning().empty())
    log.warn(lock.warning());
  // The shared-memory halo needs every rank on one node, and a window within the file size
  // limit; otherwise the halo quietly uses messages (comm/shared_window.h). Said once here
  // rather than by every MD engine of the run.
  if (deck.numerics.halo == "shared_memory" && size > 1) {
    if (!ranks_share_one_node(world))
      log.info("[numerics] halo = \"shared_memory\": the ranks are on several nodes, so the "
               "halo uses messages");
    else if (const unsigned long long limit = file_size_limit(); limit != 0)
      log.info("[numerics] halo = \"shared_memory\": a file size limit (ulimit -f) of " +
               std::to_string(limit / 1024) +
               " kB is set; where the shared-memory window's backing file would exceed it, the "
               "halo uses messages");
  }

  CheckpointPolicy policy;
  policy.file = out / "checkpoint.h5";
  policy.every_steps = options.checkpoint_every_steps.value_or(deck.output.checkpoint_every_steps);
  policy.every_seconds =
      options.checkpoint_every_seconds.value_or(deck.output.checkpoint_every_seconds);
  Checkpointer checkpointer(world, policy);
  install_stop_signal_handlers();

  RunReport report;
  report.version = GRANPACK_VERSION;
  report.build_commit = build_commit;
  report.build_dirty = build_dirty;
  report.dimension = deck.sample.dimension;
  report.n = deck.sample.n;
  report.ranks = size;
  report.deck = options.deck.string();
  try {
    if (deck.sample.dimension == 3)
      run_stages<3>(world, deck, log, out, report, checkpointer, options, state);
    else
      run_stages<2>(world, deck, log, out, report, checkpointer, options, state);

    report.wall_seconds =
        checkpointer.earlier_wall_seconds +
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    collectively(world, [&] {
      if (rank == 0)
        write_report(out / "report.json", report);
    });
  } catch (const CheckpointedStop& e) {
    log.record("stopped (exit " + std::to_string(e.exit_code()) + "): " + e.what());
    throw;
  } catch (const Error& e) {
    log.record("error (exit " + std::to_string(e.exit_code()) + "): " + e.what());
    throw;
  }
  log.info("wrote " + (out / "report.json").string());
  log.record("finished (exit 0)");
  return kExitOk;
}

std::string check_decks(MPI_Comm world, const std::vector<std::filesystem::path>& decks) {
  const int rank = rank_of(world);
  std::ostringstream os;
  for (const auto& path : decks) {
    const Deck deck = load_deck_collectively(world, path, std::nullopt);
    os << deck.file << ": ok, dimension " << deck.sample.dimension << ", n = " << deck.sample.n
       << ", " << deck.stages.size() << " stages:";
    for (const auto& st : deck.stages) {
      os << ' ' << st.kind;
      if (st.name != st.kind)
        os << " '" << st.name << "'";
      // A read stage names a file the run needs at that stage: a missing one would stop the
      // run there, after the earlier stages' work.
      if (const auto* r = std::get_if<ReadStage>(&st.params)) {
        int missing = 0;
        if (rank == 0)
          missing = std::filesystem::exists(r->file) ? 0 : 1;
        missing = broadcast_value(world, missing);
        if (missing)
          throw InputError(
              deck.file + ": stage " + std::to_string(st.index) + " '" + st.name +
              "' (read): file '" + r->file +
              "' does not exist (relative paths are taken from the working directory)");
      }
    }
    os << '\n';
  }
  return os.str();
}

} // namespace granpack
