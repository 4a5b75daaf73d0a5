// `expand` stage: homothetic expansion of the cell and of the grain centres by lambda
// ([AR] sec. IV B: lambda = 1.005 separates every contact of an A packing at kappa = 39000).
// Positions are scaled coordinates, so multiplying the cell lengths moves every centre.
// Grains are left at rest and contact histories are dropped: the pairs are separated (a pair
// that still overlaps forms a fresh contact in the next MD stage, and the hard-sphere stages
// refuse overlaps with a message).
#include <sstream>

#include "granpack/core/error.h"
#include "granpack/stages/stages.h"

namespace granpack {

template <int dim> StageReport run_stage(RunContext<dim>& ctx, const ExpandStage& e) {
  GRANPACK_CHECK(ctx.decomposition, "stage " << ctx.stage_index << " (" << ctx.stage_name
                                             << "): there is no sample to expand yet");
  const double phi0 = ctx.solid_fraction();
  ctx.system.cell.length *= e.factor;
  ctx.system.cell.rate.setZero();
  auto& p = ctx.system.particles;
  p.clear_ghosts();
  for (std::size_t i = 0; i < p.n_owned(); ++i) {
    p.velocity[i].setZero();
    p.angular_velocity[i].setZero();
  }
  ctx.system.contacts.clear();
  std::ostringstream os;
  os << "  cell and centres x " << e.factor << ": phi " << phi0 << " -> " << ctx.solid_fraction();
  ctx.log->info(os.str());
  return StageReport{};
}

template StageReport run_stage<2>(RunContext<2>&, const ExpandStage&);
template StageReport run_stage<3>(RunContext<3>&, const ExpandStage&);

} // namespace granpack
