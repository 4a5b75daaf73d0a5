#pragma once
// The stages a deck chains (docs/deck.md). Each function runs one stage on every rank
// (collective on ctx.world) and returns its report.json entry.
#include <array>

#include "granpack/io/deck.h"
#include "granpack/io/hdf5_store.h"
#include "granpack/engine/run_context.h"
#include "granpack/engine/state_file.h"

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

/// Removes the overlaps of randomly placed grains (fixed cell, soft repulsion, quench).
template <int dim> StageReport remove_overlaps(RunContext<dim>& ctx);

}  // namespace granpack
