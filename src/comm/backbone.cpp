#include "granpack/comm/backbone.h"

#include "granpack/comm/reduce.h"

namespace granpack {

template <int dim>
Backbone find_backbone(const ParticleStore<dim>& p, const Halo<dim>& halo,
                       const Decomposition<dim>& d, const std::vector<CarryingContact>& carrying,
                       int min_contacts) {
  Backbone b;
  b.rattler.assign(p.size(), 0);
  b.counts.assign(p.size(), 0.0);
  std::vector<double> flags(p.size());
  // Counts are summed over ranks, then the rattler flags are copied to the ghosts before
  // the next count, until no grain changes anywhere.
  while (true) {
    count_backbone_contacts(carrying, b.rattler, b.counts);
    halo.reverse_values(b.counts, d);
    auto fresh =
        static_cast<std::int64_t>(flag_rattlers(p.n_owned(), b.counts, min_contacts, b.rattler));
    if (global_sum(d.comm(), fresh) == 0)
      break;
    for (std::size_t i = 0; i < p.size(); ++i)
      flags[i] = b.rattler[i];
    halo.forward_values(flags, d);
    for (std::size_t i = p.n_owned(); i < p.size(); ++i)
      b.rattler[i] = flags[i] > 0.5;
  }
  std::int64_t local_r = 0, local_c = 0, local_2 = 0;
  double force_sums[2] = {0, 0}; // sum N, sum N^2 over backbone contacts
  for (std::size_t i = 0; i < p.n_owned(); ++i) {
    local_r += b.rattler[i];
    local_2 += !b.rattler[i] && b.counts[i] == 2;
  }
  for (const auto& c : carrying)
    if (!(b.rattler[c.i] || b.rattler[c.j])) {
      ++local_c;
      force_sums[0] += c.normal_force;
      force_sums[1] += c.normal_force * c.normal_force;
    }
  global_sum_in_place(d.comm(), force_sums);
  auto& m = b.metrics;
  m.n = global_sum(d.comm(), static_cast<std::int64_t>(p.n_owned()));
  m.rattlers = global_sum(d.comm(), local_r);
  m.backbone_contacts = global_sum(d.comm(), local_c);
  m.x0 = m.n ? double(m.rattlers) / double(m.n) : 0.0;
  m.z = m.n ? 2.0 * double(m.backbone_contacts) / double(m.n) : 0.0;
  m.z_star = m.x0 < 1 ? m.z / (1 - m.x0) : 0.0;
  m.x2 = m.n ? double(global_sum(d.comm(), local_2)) / double(m.n) : 0.0;
  if (m.backbone_contacts > 0) {
    const double mean = force_sums[0] / double(m.backbone_contacts);
    m.z2 = force_sums[1] / double(m.backbone_contacts) / (mean * mean);
  }
  return b;
}

template Backbone find_backbone<2>(const ParticleStore<2>&, const Halo<2>&, const Decomposition<2>&,
                                   const std::vector<CarryingContact>&, int);
template Backbone find_backbone<3>(const ParticleStore<3>&, const Halo<3>&, const Decomposition<3>&,
                                   const std::vector<CarryingContact>&, int);

} // namespace granpack
