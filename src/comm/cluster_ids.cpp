#include "granpack/comm/cluster_ids.h"

#include <unordered_map>

#include "granpack/analysis/disjoint_sets.h"
#include "granpack/comm/broadcast.h"
#include "granpack/comm/communicator.h"
#include "granpack/comm/gather.h"

namespace granpack {

template <int dim>
std::vector<double> cluster_ids(const ParticleStore<dim>& p, const Halo<dim>& halo,
                                const Decomposition<dim>& d,
                                const std::vector<CarryingContact>& pairs) {
  // Local clusters, named by their smallest id; keyed by id, so the periodic images of one
  // grain (ghosts of the same id) fall into one cluster.
  std::vector<std::pair<GlobalId, GlobalId>> links;
  links.reserve(pairs.size());
  for (const auto& c : pairs)
    links.emplace_back(p.id[c.i], p.id[c.j]);
  const auto local = smallest_member(links);
  std::vector<double> name(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    const auto it = local.find(p.id[i]);
    name[i] = double(it == local.end() ? p.id[i] : it->second);
  }
  // The owners' names on the ghosts: a ghost whose local name differs from its owner's joins
  // two clusters that only the owner's rank and this one see together.
  std::vector<double> owners = name;
  halo.forward_values(owners, d);
  std::vector<GlobalId> joins; // two names after another
  for (std::size_t g = p.n_owned(); g < p.size(); ++g)
    if (owners[g] != name[g]) {
      joins.push_back(GlobalId(name[g]));
      joins.push_back(GlobalId(owners[g]));
    }
  const std::vector<GlobalId> all = gather_on_root(d.comm(), joins);
  // Rank 0 names each joined set by its smallest member, the smallest id of the whole cluster
  // (every local name is the smallest id of its part); the renamings go to every rank.
  std::vector<GlobalId> renamed; // old name, new name, ...
  if (rank_of(d.comm()) == 0) {
    std::vector<std::pair<GlobalId, GlobalId>> pairs_of_names;
    for (std::size_t k = 0; k + 1 < all.size(); k += 2)
      pairs_of_names.emplace_back(all[k], all[k + 1]);
    for (const auto& [old_name, new_name] : smallest_member(pairs_of_names))
      if (old_name != new_name) {
        renamed.push_back(old_name);
        renamed.push_back(new_name);
      }
  }
  const auto count = broadcast_value(d.comm(), std::int64_t(renamed.size()));
  renamed.resize(std::size_t(count));
  broadcast_in_place(d.comm(), renamed);
  std::unordered_map<GlobalId, GlobalId> rename;
  for (std::size_t k = 0; k + 1 < renamed.size(); k += 2)
    rename.emplace(renamed[k], renamed[k + 1]);
  std::vector<double> out(p.n_owned());
  for (std::size_t i = 0; i < out.size(); ++i) {
    const auto it = rename.find(GlobalId(name[i]));
    out[i] = it == rename.end() ? name[i] : double(it->second);
  }
  return out;
}

template std::vector<double> cluster_ids<2>(const ParticleStore<2>&, const Halo<2>&,
                                            const Decomposition<2>&,
                                            const std::vector<CarryingContact>&);
template std::vector<double> cluster_ids<3>(const ParticleStore<3>&, const Halo<3>&,
                                            const Decomposition<3>&,
                                            const std::vector<CarryingContact>&);

} // namespace granpack
