// `set` stage: change the contact law between stages (e.g. friction 0 -> 0.3, [AR] C).
#include <sstream>

#include "granpack/stages/stages.h"

namespace granpack {

template <int dim> StageReport run_stage(RunContext<dim>& ctx, const SetStage& p) {
  std::ostringstream os;
  os << "  set:";
  if (p.friction) {
    os << " friction " << ctx.contact_law.friction << " -> " << *p.friction;
    ctx.contact_law.friction = *p.friction;
  }
  if (p.damping) {
    os << " damping " << ctx.contact_law.damping_ratio << " -> " << *p.damping;
    ctx.contact_law.damping_ratio = *p.damping;
  }
  if (p.rolling_damping) {
    os << " rolling_damping " << ctx.contact_law.rolling_damping << " -> " << *p.rolling_damping;
    ctx.contact_law.rolling_damping = *p.rolling_damping;
  }
  ctx.log->info(os.str());
  return StageReport{};
}

template StageReport run_stage<2>(RunContext<2>&, const SetStage&);
template StageReport run_stage<3>(RunContext<3>&, const SetStage&);

} // namespace granpack
