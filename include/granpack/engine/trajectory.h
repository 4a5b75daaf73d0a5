#pragma once
// In-run trajectories ([output] trajectory_every, docs/deck.md): every N steps the MD engine
// appends a snapshot of the state (grains, contacts, the contact network) to OUT/trajectory.h5
// and rewrites the sidecar OUT/trajectory.xdmf, a temporal collection that ParaView plays
// (docs/visualisation.md). A fresh run starts a new trajectory; a restarted one continues it,
// after deleting the snapshots the interrupted run wrote after its checkpoint, so that a
// restarted run's trajectory equals the uninterrupted run's. Collective on ctx.world.
#include <filesystem>

#include "granpack/engine/run_context.h"

namespace granpack {

/// OUT/trajectory.h5.
template <int dim> std::filesystem::path trajectory_path(const RunContext<dim>& ctx) {
  return ctx.output_dir / "trajectory.h5";
}

/// At the start of a run with trajectories on: a fresh run (restarted = false) removes an
/// earlier trajectory of the output directory; a restart deletes the snapshots after the
/// checkpoint's step and rewrites the sidecar. Nothing when trajectory_every is 0.
template <int dim> void start_trajectory(RunContext<dim>& ctx, bool restarted);

/// True when the step just completed (ctx.system.step) is one to snapshot.
template <int dim> bool trajectory_due(const RunContext<dim>& ctx) {
  const auto every = ctx.deck ? ctx.deck->output.trajectory_every : 0;
  return every > 0 && !ctx.output_dir.empty() && ctx.system.step % every == 0;
}

/// Appends the current state as a snapshot and rewrites the sidecar.
template <int dim> void write_snapshot(RunContext<dim>& ctx);

extern template void start_trajectory<2>(RunContext<2>&, bool);
extern template void start_trajectory<3>(RunContext<3>&, bool);
extern template void write_snapshot<2>(RunContext<2>&);
extern template void write_snapshot<3>(RunContext<3>&);

} // namespace granpack
