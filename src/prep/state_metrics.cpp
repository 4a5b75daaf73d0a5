#include "granpack/prep/state_metrics.h"

namespace granpack {

template <int dim>
StateMetrics state_metrics(RunContext<dim>& ctx, const MdEngine<dim>& engine, double threshold,
                           int min_contacts) {
  std::vector<CarryingContact> carrying;
  engine.for_each_contact([&](std::size_t i, std::size_t j, const Vec<dim>&,
                              const ContactState<dim>& st) {
    if (st.normal_force > threshold) carrying.push_back({i, j, st.normal_force});
  });
  return find_backbone(ctx.system.particles, engine.halo(), *ctx.decomposition, carrying,
                       min_contacts)
      .metrics;
}

template StateMetrics state_metrics<2>(RunContext<2>&, const MdEngine<2>&, double, int);
template StateMetrics state_metrics<3>(RunContext<3>&, const MdEngine<3>&, double, int);

}  // namespace granpack
