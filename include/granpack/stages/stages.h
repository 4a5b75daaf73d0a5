#pragma once
// The stages a deck chains (docs/deck.md): the runner of each kind of the registry
// StageParams (io/stage_params.h), defined in the stage's own file and instantiated there for
// 2 and 3 dimensions. run_stage runs one stage on every rank (collective on ctx.world) and
// returns its report.json entry; `granpack run` calls it on each stage's parameters, so a
// kind without a runner here does not compile.
#include <array>

#include "granpack/engine/run_context.h"
#include "granpack/engine/state_file.h"
#include "granpack/io/deck.h"
#include "granpack/io/hdf5_store.h"

namespace granpack {

template <int dim> StageReport run_stage(RunContext<dim>& ctx, const LatticeStage& p);
template <int dim> StageReport run_stage(RunContext<dim>& ctx, const RandomStage& p);
template <int dim> StageReport run_stage(RunContext<dim>& ctx, const CompressStage& p);
template <int dim> StageReport run_stage(RunContext<dim>& ctx, const SetStage& p);
template <int dim> StageReport run_stage(RunContext<dim>& ctx, const WriteStage& p);
template <int dim> StageReport run_stage(RunContext<dim>& ctx, const ReadStage& p);
template <int dim> StageReport run_stage(RunContext<dim>& ctx, const EdGasStage& p);
template <int dim> StageReport run_stage(RunContext<dim>& ctx, const LsCompressStage& p);
template <int dim> StageReport run_stage(RunContext<dim>& ctx, const ExpandStage& p);
template <int dim> StageReport run_stage(RunContext<dim>& ctx, const PressureStepsStage& p);
template <int dim> StageReport run_stage(RunContext<dim>& ctx, const FixRattlersStage& p);
template <int dim> StageReport run_stage(RunContext<dim>& ctx, const AggregateStage& p);
template <int dim> StageReport run_stage(RunContext<dim>& ctx, const StiffenStage& p);
template <int dim> StageReport run_stage(RunContext<dim>& ctx, const DivalentLaunchStage& p);

/// Removes the overlaps of randomly placed grains (fixed cell, soft repulsion, quench).
template <int dim> StageReport remove_overlaps(RunContext<dim>& ctx);

} // namespace granpack
