#pragma once
// In-run trajectories ([output] trajectory_every, trajectory_every_time, trajectory_stage_ends;
// docs/deck.md): every N steps, after each MD step that crosses a multiple of Δt of simulated
// time, and at the end of every stage, the run appends a snapshot of the state (grains,
// contacts, the contact network) to OUT/trajectory.h5 and rewrites the sidecar
// OUT/trajectory.xdmf, a temporal collection that ParaView plays (docs/visualisation.md).
// Snapshots are named by the step counter: a stage end at the step of an existing snapshot
// (the step rule's in the stage's last step, or the end of an earlier stage that took no MD
// step) replaces it, so that a step holds the last state the run had at it. A fresh run starts
// a new trajectory; a restarted one continues it, after deleting the snapshots the interrupted
// run wrote after its checkpoint, so that a restarted run's trajectory equals the
// uninterrupted run's. Collective on ctx.world.
#include <cmath>
#include <filesystem>

#include "granpack/engine/run_context.h"

namespace granpack {

/// OUT/trajectory.h5.
template <int dim> std::filesystem::path trajectory_path(const RunContext<dim>& ctx) {
  return ctx.output_dir / "trajectory.h5";
}

/// At the start of a run with trajectories on: a fresh run (restarted = false) removes an
/// earlier trajectory of the output directory; a restart deletes the snapshots after the
/// checkpoint's step and rewrites the sidecar. Nothing when every trajectory key is off.
template <int dim> void start_trajectory(RunContext<dim>& ctx, bool restarted);

/// True when the MD step just completed (ctx.system.step, the simulated time going from
/// `time_before` to ctx.system.time) is one to snapshot: the step counter is a multiple of
/// trajectory_every, or the step crossed a multiple of trajectory_every_time (floor(t / Δt)
/// grew: the first step at or past each multiple; a stage that restarts the time at 0 starts
/// counting again). A function of the step and the two times alone, which a restart restores
/// exactly.
template <int dim> bool trajectory_due(const RunContext<dim>& ctx, double time_before) {
  if (!ctx.deck || ctx.output_dir.empty())
    return false;
  const auto& o = ctx.deck->output;
  if (o.trajectory_every > 0 && ctx.system.step % o.trajectory_every == 0)
    return true;
  const double every = o.trajectory_every_time;
  return every > 0 && std::floor(ctx.system.time / every) > std::floor(time_before / every);
}

/// Appends the current state as a snapshot and rewrites the sidecar.
template <int dim> void write_snapshot(RunContext<dim>& ctx);

/// At the end of a stage, with trajectory_stage_ends (and a sample): appends the current state,
/// replacing a snapshot of the same step. Nothing otherwise.
template <int dim> void stage_end_snapshot(RunContext<dim>& ctx);

extern template void start_trajectory<2>(RunContext<2>&, bool);
extern template void start_trajectory<3>(RunContext<3>&, bool);
extern template void write_snapshot<2>(RunContext<2>&);
extern template void write_snapshot<3>(RunContext<3>&);
extern template void stage_end_snapshot<2>(RunContext<2>&);
extern template void stage_end_snapshot<3>(RunContext<3>&);

} // namespace granpack
