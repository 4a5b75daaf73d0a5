#pragma once
// The stages a deck chains (docs/deck.md). Each function runs one stage on every rank
// (collective on ctx.world) and returns its report.json entry.
#include <array>

#include "granpack/io/deck.h"
#include "granpack/io/hdf5_store.h"
#include "granpack/engine/run_context.h"

namespace granpack {

template <int dim> StageReport run_lattice(RunContext<dim>& ctx, const LatticeStage& p);
template <int dim> StageReport run_random(RunContext<dim>& ctx, const RandomStage& p);
template <int dim> StageReport run_compress(RunContext<dim>& ctx, const CompressStage& p);
template <int dim> StageReport run_set(RunContext<dim>& ctx, const SetStage& p);
template <int dim> StageReport run_write(RunContext<dim>& ctx, const WriteStage& p);
template <int dim> StageReport run_read(RunContext<dim>& ctx, const ReadStage& p);
template <int dim> StageReport run_ed_gas(RunContext<dim>& ctx, const EdGasStage& p);
template <int dim> StageReport run_ls_compress(RunContext<dim>& ctx, const LsCompressStage& p);
template <int dim> StageReport run_expand(RunContext<dim>& ctx, const ExpandStage& p);
template <int dim> StageReport run_pressure_steps(RunContext<dim>& ctx, const PressureStepsStage& p);
template <int dim> StageReport run_fix_rattlers(RunContext<dim>& ctx, const FixRattlersStage& p);
template <int dim> StageReport run_aggregate(RunContext<dim>& ctx, const AggregateStage& p);
template <int dim> StageReport run_stiffen(RunContext<dim>& ctx, const StiffenStage& p);

/// Makes a configuration read from a file the sample: grains, contacts and cell (rate kept),
/// a domain decomposition (the given grid, else one chosen from the cell's shape) and the
/// grains and contacts moved to their spatial owners. Collective. Used by `read` and restarts.
template <int dim> void adopt_configuration(RunContext<dim>& ctx, Configuration<dim>&& c,
                                            const std::array<int, dim>* grid = nullptr);

/// Removes the overlaps of randomly placed grains (fixed cell, soft repulsion, quench).
template <int dim> StageReport remove_overlaps(RunContext<dim>& ctx);

/// Writes the current state as an HDF5 configuration file (with its XDMF sidecar); with a
/// run_state (prep/checkpoint.h) the file is a checkpoint.
template <int dim> void write_state(RunContext<dim>& ctx, const std::filesystem::path& file,
                                    const std::string& run_state = {});

}  // namespace granpack
