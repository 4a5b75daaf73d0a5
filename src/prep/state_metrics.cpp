#include "granpack/prep/state_metrics.h"

#include "granpack/analysis/coordination.h"
#include "granpack/comm/reduce.h"

namespace granpack {

template <int dim>
StateMetrics state_metrics(RunContext<dim>& ctx, const MdEngine<dim>& engine, double threshold,
                           int min_contacts) {
  const auto& p = ctx.system.particles;
  const auto& d = *ctx.decomposition;
  std::vector<CarryingContact> carrying;
  engine.for_each_contact([&](std::size_t i, std::size_t j, const Vec<dim>&,
                              const ContactState<dim>& st) {
    if (st.normal_force > threshold) carrying.push_back({i, j, st.normal_force});
  });
  std::vector<std::uint8_t> rattler(p.size(), 0);
  std::vector<double> counts(p.size()), flags(p.size());
  // Iterate to the fixed point: counts are summed over ranks (a contact's ends may live on
  // two ranks), rattler flags copied to ghosts before recounting.
  while (true) {
    count_backbone_contacts(carrying, rattler, counts);
    engine.halo().reverse_values(counts, d);
    std::int64_t fresh = static_cast<std::int64_t>(flag_rattlers(p.n_owned(), counts, min_contacts, rattler));
    if (global_sum(ctx.world, fresh) == 0) break;
    for (std::size_t i = 0; i < p.size(); ++i) flags[i] = rattler[i];
    engine.halo().forward_values(flags, d);
    for (std::size_t i = p.n_owned(); i < p.size(); ++i) rattler[i] = flags[i] > 0.5;
  }
  std::int64_t local_r = 0;
  for (std::size_t i = 0; i < p.n_owned(); ++i) local_r += rattler[i];
  std::int64_t local_c = 0;
  for (const auto& c : carrying) local_c += !(rattler[c.i] || rattler[c.j]);
  StateMetrics m;
  m.n = global_sum(ctx.world, static_cast<std::int64_t>(p.n_owned()));
  m.rattlers = global_sum(ctx.world, local_r);
  m.backbone_contacts = global_sum(ctx.world, local_c);
  m.x0 = double(m.rattlers) / double(m.n);
  m.z = 2.0 * double(m.backbone_contacts) / double(m.n);
  m.z_star = m.x0 < 1 ? m.z / (1 - m.x0) : 0.0;
  return m;
}

template StateMetrics state_metrics<2>(RunContext<2>&, const MdEngine<2>&, double, int);
template StateMetrics state_metrics<3>(RunContext<3>&, const MdEngine<3>&, double, int);

}  // namespace granpack
