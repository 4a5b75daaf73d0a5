// `read` stage: the sample is a configuration file written by granpack (any rank count):
// grains, contacts with their history and the cell. The deck's material applies from here on
// (the file's deck is not consulted), so a packing can be continued with new parameters
// (e.g. [AR] procedure C from a stored A state). The rattlers the file's run fixed
// (treatment II, /network/fixed_rattler) stay flagged until a later stage moves the grains.
#include <algorithm>
#include <sstream>

#include "granpack/comm/reduce.h"
#include "granpack/core/error.h"
#include "granpack/engine/checkpoint.h"
#include "granpack/io/hdf5_store.h"
#include "granpack/stages/stages.h"

namespace granpack {

template <int dim> StageReport run_stage(RunContext<dim>& ctx, const ReadStage& r) {
  GRANPACK_CHECK(ctx.system.particles.size() == 0,
                 "stage " << ctx.stage_index
                          << " (read) needs an empty sample: it must come first");
  FileMeta meta;
  Configuration<dim> c;
  {
    ScopedPhase io(ctx.stage_timers.io);
    meta = read_file_meta(ctx.world, r.file);
    if (meta.dimension != dim)
      throw InputError(ctx.deck->file + ": stage[" + std::to_string(ctx.stage_index) +
                       "] (read) file = \"" + r.file + "\" holds a " +
                       std::to_string(meta.dimension) + "D sample, the deck is " +
                       std::to_string(dim) + "D");
    c = read_configuration<dim>(ctx.world, r.file);
    // Treatment II's flags describe the grains as the file holds them, which this stage keeps
    // as `set` and `write` do (run_deck cleared the list as the stage began): a
    // configuration's /network/fixed_rattler, a checkpoint's /run_state list.
    ctx.fixed_rattlers = meta.kind == "checkpoint"
                             ? parse_run_state(meta.run_state, r.file).fixed_rattlers
                             : read_fixed_rattlers(ctx.world, r.file);
    std::sort(ctx.fixed_rattlers.begin(), ctx.fixed_rattlers.end()); // binary_search'ed
  }
  adopt_configuration(ctx, std::move(c));
  ctx.system.cell.rate.setZero();
  const std::int64_t n =
      global_sum(ctx.world, static_cast<std::int64_t>(ctx.system.particles.n_owned()));
  if (n != ctx.deck->sample.n)
    throw InputError(ctx.deck->file + ": stage[" + std::to_string(ctx.stage_index) +
                     "] (read) file = \"" + r.file + "\" holds " + std::to_string(n) +
                     " grains but [sample] n = " + std::to_string(ctx.deck->sample.n));
  std::ostringstream os;
  os << "  read " << r.file << ": " << n << " grains, " << meta.n_contacts << " contacts, stage '"
     << meta.stage_name << "' of the run that wrote it";
  if (!ctx.fixed_rattlers.empty())
    os << ", " << ctx.fixed_rattlers.size() << " rattlers fixed by its fix_rattlers stage";
  ctx.log->info(os.str());
  return StageReport{};
}

template StageReport run_stage<2>(RunContext<2>&, const ReadStage&);
template StageReport run_stage<3>(RunContext<3>&, const ReadStage&);

} // namespace granpack
