#include "granpack/app/ensemble_run.h"

#include <algorithm>
#include <vector>

#include "granpack/comm/barrier.h"
#include "granpack/comm/broadcast.h"
#include "granpack/comm/collective_error.h"
#include "granpack/comm/communicator.h"
#include "granpack/comm/reduce.h"
#include "granpack/core/error.h"
#include "granpack/engine/stop_signals.h"
#include "granpack/io/log.h"

namespace granpack {

namespace {

/// Ranks per sample: the option, or an even share of the ranks among the samples.
int choose_ranks_per_sample(int size, const EnsembleOptions& o) {
  if (o.samples < 1)
    throw InputError("--samples " + std::to_string(o.samples) + ": must be at least 1");
  int r = o.ranks_per_sample;
  if (r == 0)
    r = (o.samples < size && size % o.samples == 0) ? size / o.samples : 1;
  if (r < 1 || size % r != 0)
    throw InputError("--ranks-per-sample " + std::to_string(r) + ": must divide the " +
                     std::to_string(size) + " MPI ranks of the job (e.g. " + std::to_string(size) +
                     " ranks: 1 or " + std::to_string(size) + ")");
  return r;
}

enum class SampleStart { fresh, resume, finished };

/// What sample `dir` needs; decided on the group's rank 0 and broadcast.
SampleStart sample_start(MPI_Comm group, const std::filesystem::path& dir, bool resume) {
  int what = static_cast<int>(SampleStart::fresh);
  if (rank_of(group) == 0 && resume) {
    if (std::filesystem::exists(dir / "report.json"))
      what = static_cast<int>(SampleStart::finished);
    else if (std::filesystem::exists(dir / "checkpoint.h5"))
      what = static_cast<int>(SampleStart::resume);
  }
  return static_cast<SampleStart>(broadcast_value(group, what));
}

/// The job's exit code from the groups': an error beats a checkpointed stop beats success.
int combine_codes(MPI_Comm world, int code) {
  const int error = global_max(world, (code != kExitOk && code != kExitCheckpointed) ? code : 0);
  const int stopped = global_max(world, code == kExitCheckpointed ? 1 : 0);
  return error ? error : (stopped ? kExitCheckpointed : kExitOk);
}

} // namespace

std::filesystem::path sample_directory(const std::filesystem::path& out, std::uint64_t seed) {
  return out / ("sample_" + std::to_string(seed));
}

int run_ensemble(MPI_Comm world, const EnsembleOptions& o) {
  install_stop_signal_handlers();
  const int size = size_of(world);
  const int per_sample = choose_ranks_per_sample(size, o);
  // Every sample's deck must start: check them all on every rank before any run.
  for (int k = 0; k < o.samples; ++k)
    load_deck_collectively(world, o.run.deck, o.first_seed + static_cast<std::uint64_t>(k));
  std::filesystem::path out = o.run.output_dir;
  if (out.empty())
    out = std::filesystem::path("out") / o.run.deck.stem();
  collectively(world, [&] {
    if (rank_of(world) != 0)
      return;
    std::error_code ec;
    std::filesystem::create_directories(out, ec);
    if (ec)
      throw InputError("cannot create the output directory " + out.string() + ": " + ec.message());
  });

  const int groups = size / per_sample;
  const int color = rank_of(world) / per_sample;
  MPI_Comm group = split_communicator(world, color, rank_of(world));
  Log log(rank_of(world) == 0, false);
  log.info("ensemble: " + std::to_string(o.samples) + " samples of " + o.run.deck.string() +
           " (seeds " + std::to_string(o.first_seed) + ".." +
           std::to_string(o.first_seed + static_cast<std::uint64_t>(o.samples) - 1) + ") in " +
           out.string() + ", " + std::to_string(groups) + " at a time on " +
           std::to_string(per_sample) + " rank(s) each");

  int code = kExitOk;
  for (int k = color; k < o.samples; k += groups) {
    const std::uint64_t seed = o.first_seed + static_cast<std::uint64_t>(k);
    // A stop signal between two samples: start no new one.
    if (global_max(group, stop_signal_received() != 0 ? 1 : 0)) {
      code = std::max(code, static_cast<int>(kExitCheckpointed));
      break;
    }
    RunOptions run = o.run;
    run.output_dir = sample_directory(out, seed);
    run.seed = seed;
    run.terminal_prefix = "[sample " + std::to_string(seed) + "] ";
    Log say(rank_of(group) == 0, false);
    say.set_terminal_prefix(run.terminal_prefix);
    const SampleStart start = sample_start(group, run.output_dir, o.resume);
    if (start == SampleStart::finished) {
      say.info("finished earlier (" + (run.output_dir / "report.json").string() + "): skipped");
      continue;
    }
    if (start == SampleStart::resume)
      run.restart = run.output_dir / "checkpoint.h5";
    try {
      const int c = run_deck(group, run);
      if (c != kExitOk)
        code = code == kExitOk ? c : code;
    } catch (const CheckpointedStop& e) {
      say.info(e.what());
      if (code == kExitOk)
        code = e.exit_code();
      break; // the job is asked to end: no further sample
    } catch (const Error& e) {
      // Collective on the group: the other samples go on; the job's exit code says it.
      say.warn("sample " + std::to_string(seed) + " failed: " + std::string(e.what()));
      if (code == kExitOk || code == kExitCheckpointed)
        code = e.exit_code();
    }
  }
  free_communicator(group);
  idle_barrier(world);
  const int job = combine_codes(world, code);
  log.info("ensemble: " +
           std::string(job == kExitOk ? "every sample finished"
                       : job == kExitCheckpointed
                           ? "stopped on a signal; --restart resumes the unfinished samples"
                           : "a sample failed (see its log.txt)") +
           "; `granpack ensemble " + out.string() + "` gathers them");
  return job;
}

} // namespace granpack
