#include "granpack/engine/trajectory.h"

#include "granpack/comm/collective_error.h"
#include "granpack/comm/communicator.h"
#include "granpack/engine/state_file.h"
#include "granpack/io/xdmf.h"

namespace granpack {

namespace {
/// Rank 0 rewrites OUT/trajectory.xdmf from the file's index (the file closed everywhere).
template <int dim> void write_sidecar(RunContext<dim>& ctx) {
  const auto path = trajectory_path(ctx);
  const auto index = read_trajectory_index(ctx.world, path);
  collectively(ctx.world, [&] {
    if (rank_of(ctx.world) != 0)
      return;
    std::vector<XdmfParticles> frames;
    // The time of the series is the step counter: the simulated time starts again at 0 in
    // some stages (random, overlap removal), the steps never do.
    for (const auto& s : index)
      frames.push_back({path.filename().string(), dim, s.n_particles, static_cast<double>(s.step),
                        s.network ? s.n_contacts : -1, s.group});
    write_trajectory_xdmf(xdmf_path_for(path), path.filename().string(), frames);
  });
}
} // namespace

template <int dim> void start_trajectory(RunContext<dim>& ctx, bool restarted) {
  if (!ctx.deck || !ctx.deck->output.trajectory())
    return;
  const auto path = trajectory_path(ctx);
  if (restarted) {
    prune_trajectory(ctx.world, path, ctx.system.step);
    if (std::filesystem::exists(path))
      write_sidecar(ctx);
    return;
  }
  collectively(ctx.world, [&] {
    if (rank_of(ctx.world) != 0)
      return;
    for (const auto& p : {path, xdmf_path_for(path)}) {
      std::error_code ec;
      std::filesystem::remove(p, ec);
      if (ec)
        throw WriteError("cannot remove the earlier " + p.string() + ": " + ec.message());
    }
  });
}

template <int dim> void write_snapshot(RunContext<dim>& ctx) {
  ScopedPhase io(ctx.stage_timers.io);
  Configuration<dim> c = state_configuration(ctx, {});
  c.meta.deck_text.clear(); // stored once, at the file's root
  append_snapshot<dim>(ctx.world, trajectory_path(ctx), c, ctx.deck->text);
  write_sidecar(ctx);
}

template <int dim> void stage_end_snapshot(RunContext<dim>& ctx) {
  if (!ctx.deck || !ctx.deck->output.trajectory_stage_ends || ctx.output_dir.empty() ||
      !ctx.decomposition)
    return;
  // No snapshot comes after this step yet: deleting those after step - 1 removes only the
  // snapshot of this step, if there is one.
  prune_trajectory(ctx.world, trajectory_path(ctx), ctx.system.step - 1);
  write_snapshot(ctx);
}

template void start_trajectory<2>(RunContext<2>&, bool);
template void start_trajectory<3>(RunContext<3>&, bool);
template void write_snapshot<2>(RunContext<2>&);
template void write_snapshot<3>(RunContext<3>&);
template void stage_end_snapshot<2>(RunContext<2>&);
template void stage_end_snapshot<3>(RunContext<3>&);

} // namespace granpack
