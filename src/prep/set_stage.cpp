// `set` stage: change material parameters between stages (e.g. friction 0 -> 0.3, [AR] C).
#include <sstream>

#include "granpack/prep/stages.h"

namespace granpack {

template <int dim> StageReport run_set(RunContext<dim>& ctx, const SetStage& p) {
  std::ostringstream os;
  os << "  set:";
  if (p.friction) {
    os << " friction " << ctx.material.friction << " -> " << *p.friction;
    ctx.material.friction = *p.friction;
  }
  if (p.damping) {
    os << " damping " << ctx.material.damping << " -> " << *p.damping;
    ctx.material.damping = *p.damping;
  }
  ctx.log->info(os.str());
  return StageReport{};
}

template StageReport run_set<2>(RunContext<2>&, const SetStage&);
template StageReport run_set<3>(RunContext<3>&, const SetStage&);

}  // namespace granpack
