// `write` stage: the state as a configuration file (engine/state_file.h writes it).

#include "granpack/core/error.h"
#include "granpack/stages/stages.h"

namespace granpack {

template <int dim> StageReport run_stage(RunContext<dim>& ctx, const WriteStage& p) {
  GRANPACK_CHECK(ctx.decomposition, "stage " << ctx.stage_index
                                             << " (write): there is no sample yet; put a "
                                                "lattice or random stage before it");
  write_state(ctx, ctx.output_dir / p.file);
  ctx.log->info("  wrote " + (ctx.output_dir / p.file).string());
  return StageReport{};
}

template StageReport run_stage<2>(RunContext<2>&, const WriteStage&);
template StageReport run_stage<3>(RunContext<3>&, const WriteStage&);

} // namespace granpack
