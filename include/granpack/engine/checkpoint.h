#pragma once
// Checkpoints of a running deck (docs/long-jobs.md): when to write one, what it holds beyond
// the grains, and how a restart finds its place again.
//
// A checkpoint is an HDF5 configuration (kind "checkpoint", io/hdf5_store.h) - whose group
// /parameters holds, as in every file a run writes, the contact law and stress target the
// stages left in the RunContext - plus /run_state, a JSON text with the stage in progress,
// the completed stages' report entries, the domain grid, and - for a checkpoint taken inside
// a stage - one frame of internal state per nested stage (pressure_steps -> compress). Two
// moments are used:
//  * between stages ("boundary"): nothing to resume inside a stage;
//  * inside an MD stage, in the middle of a time step, right after a forced neighbour
//    rebuild (md_engine.h): positions are drifted, velocities half-kicked, forces not yet
//    computed. The rebuild puts every rank's grains in a canonical order (spatial bins, then id:
//    a function of the stored positions and ids), so the restarted run, which
//    performs the same rebuild on the stored state, repeats the interrupted run bit for bit
//    on the same rank count.
#include <mpi.h>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "granpack/io/deck.h"
#include "granpack/io/report.h"
#include "granpack/io/state_parameters.h"

namespace granpack {

template <int dim> struct RunContext;

/// Bits of the per-step request the ranks agree on (bitwise OR all-reduce in the MD step).
enum StepRequest : int {
  kRequestRebuild = 1,    ///< a grain moved more than half the skin
  kRequestCheckpoint = 2, ///< the step or wall-time interval has elapsed
  kRequestStop = 4,       ///< a stop signal arrived: checkpoint, then exit 75
};

/// Settings: the deck's [output] values, possibly overridden on the command line.
struct CheckpointPolicy {
  std::filesystem::path file;   ///< DIR/checkpoint.h5
  std::int64_t every_steps = 0; ///< 0: off
  double every_seconds = 0;     ///< 0: off
  bool enabled() const { return every_steps > 0 || every_seconds > 0; }
};

class Checkpointer {
public:
  Checkpointer(MPI_Comm world, CheckpointPolicy policy);

  /// This rank's request bits (kRequestCheckpoint, kRequestStop) for the step that will
  /// complete step number `step_after`. Wall time is judged on rank 0 only.
  int local_request(std::int64_t step_after) const;
  /// The same without the step schedule: the wall-time interval and stop signals only (the
  /// event-driven stages, which have no time steps).
  int clock_request() const;
  /// The same, all-reduced (collective; for stage boundaries).
  int global_request(std::int64_t step_after) const;

  /// Writes DIR/checkpoint.h5 atomically (collective). mid_stage: inside stage
  /// ctx.stage_index, whose frames (ctx.frames) are stored; otherwise after it (a restart
  /// runs the next stage).
  template <int dim> void write(RunContext<dim>& ctx, bool mid_stage);

  /// Throws CheckpointedStop (exit 75) on every rank if `bits` has kRequestStop.
  void stop_if_requested(int bits, std::int64_t step) const;

  /// For the MD step, given its all-reduced `bits`: whether to write the checkpoint they ask
  /// for (kRequestCheckpoint) now. A checkpoint needs a neighbour-list rebuild, which changes
  /// the order of floating-point sums; taken at a step that rebuilds anyway
  /// (kRequestRebuild), it changes nothing, and the continued run is the uninterrupted one
  /// bit for bit, whatever the step and the reason (signal, schedule). So a request is
  /// deferred to the next such step and remembered (local_request returns it, identically on
  /// every rank) -- at most kMaxDeferredSteps steps, then forced (and logged so).
  bool take_now(int bits);
  static constexpr std::int64_t kMaxDeferredSteps = 1000;

  /// Completed stages' report entries (run_deck appends; restored on restart).
  std::vector<StageReport>* completed = nullptr;
  /// Wall seconds spent by the runs before this one (restored on restart).
  double earlier_wall_seconds = 0;
  int written() const { return written_; }
  const CheckpointPolicy& policy() const { return policy_; }

private:
  MPI_Comm world_;
  CheckpointPolicy policy_;
  std::chrono::steady_clock::time_point last_, start_;
  int rank_ = 0;
  int written_ = 0;
  int deferred_ = 0;                ///< request bits awaiting a list rebuild (take_now)
  std::int64_t deferred_steps_ = 0; ///< steps they have waited (> kMaxDeferredSteps: forced)
};

/// What a checkpoint says of the run beyond the grains (parsed /run_state).
struct RunState {
  int stage_index = 0; ///< the stage to run (mid_stage: the one in progress)
  bool mid_stage = false;
  int ranks = 0;         ///< rank count of the writing run
  std::vector<int> grid; ///< its domain grid
  /// Its cut planes per axis (grid[a] + 1 each) when load balancing had moved them; empty for
  /// the uniform grid.
  std::vector<std::vector<double>> cuts;
  std::vector<StageReport> completed;
  std::vector<nlohmann::json> frames; ///< outermost stage first
  double wall_seconds = 0;
  /// RunContext::fixed_rattlers, grain ids (absent from the text when empty).
  std::vector<std::int64_t> fixed_rattlers;
  /// Checkpoints written before /parameters existed (run_state format 1) stored here what the
  /// stages had changed: restored over the deck's [material] (legacy_parameters).
  struct Legacy {
    double friction = 0, damping = 0;                          ///< as `set` stages left them
    std::optional<double> normal_stiffness, rolling_stiffness; ///< `stiffen` (absent before it)
    std::vector<double> stress; ///< the last compress stage's target (empty: none)
    std::vector<bool> fixed;
    double pressure = 0;
  };
  std::optional<Legacy> legacy;
};

/// Parses /run_state; throws InputError naming `file` if it is not one.
RunState parse_run_state(const std::string& text, const std::string& file);

/// The parameters of a checkpoint without /parameters (state.legacy set): the deck's material
/// with the stored changes, and the stored stress target, attributed to the last compress or
/// pressure_steps stage run before the checkpoint (the stage is only a label).
StateParameters legacy_parameters(const RunState& state, const Deck& deck);

/// Refuses (InputError, naming what differs) a restart whose deck differs from the
/// checkpoint's in anything but [output]; with `allow_later_stages`, stages after the one in
/// progress may also differ (or be added/removed).
void check_restart_deck(const Deck& original, const Deck& now, const RunState& state,
                        bool allow_later_stages, const std::string& checkpoint_file);

/// Exact double <-> JSON (hexadecimal bit pattern; also carries inf and NaN).
nlohmann::json exact(double v);
double exact_double(const nlohmann::json& j);

} // namespace granpack
