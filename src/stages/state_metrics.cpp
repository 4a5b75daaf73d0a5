#include "granpack/stages/state_metrics.h"

#include "granpack/comm/reduce.h"

namespace granpack {

template <int dim>
StateMetrics state_metrics(RunContext<dim>& ctx, const MdEngine<dim>& engine, double threshold,
                           int min_contacts) {
  std::vector<CarryingContact> carrying;
  engine.for_each_contact(
      [&](std::size_t i, std::size_t j, const Vec<dim>&, const ContactState<dim>& st) {
        if (st.normal_force > threshold)
          carrying.push_back({i, j, st.normal_force});
      });
  return find_backbone(ctx.system.particles, engine.halo(), *ctx.decomposition, carrying,
                       min_contacts)
      .metrics;
}

template <int dim>
CohesiveCoordination cohesive_coordination(RunContext<dim>& ctx, const MdEngine<dim>& engine,
                                           double threshold) {
  const auto& radius = ctx.system.particles.radius;
  const ContactLaw<dim>& law = engine.law();
  std::int64_t plus = 0, minus = 0, zero = 0, distant = 0;
  engine.for_each_contact(
      [&](std::size_t i, std::size_t j, const Vec<dim>& r, const ContactState<dim>& st) {
        const double n = st.normal_force + law.attraction(radius[i] + radius[j] - r.norm());
        if (n > threshold)
          ++plus;
        else if (n < -threshold)
          ++minus;
        else
          ++zero;
        if (st.flags & kDistant)
          ++distant;
      });
  const double grains = double(global_sum(ctx.world, std::int64_t(ctx.system.particles.n_owned())));
  CohesiveCoordination c;
  c.z_plus = 2.0 * double(global_sum(ctx.world, plus)) / grains;
  c.z_minus = 2.0 * double(global_sum(ctx.world, minus)) / grains;
  c.z_zero = 2.0 * double(global_sum(ctx.world, zero)) / grains;
  c.z = c.z_plus + c.z_minus + c.z_zero;
  const double all = c.z * grains / 2.0;
  c.distant_fraction = all > 0 ? double(global_sum(ctx.world, distant)) / all : 0.0;
  return c;
}

template CohesiveCoordination cohesive_coordination<2>(RunContext<2>&, const MdEngine<2>&, double);
template CohesiveCoordination cohesive_coordination<3>(RunContext<3>&, const MdEngine<3>&, double);
template StateMetrics state_metrics<2>(RunContext<2>&, const MdEngine<2>&, double, int);
template StateMetrics state_metrics<3>(RunContext<3>&, const MdEngine<3>&, double, int);

} // namespace granpack
