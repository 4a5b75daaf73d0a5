#include "granpack/comm/migration.h"

#include <mpi.h>

#include <unordered_map>

#include "granpack/comm/particle_packing.h"
#include "granpack/core/error.h"

namespace granpack {

template <int dim> std::size_t migrate(System<dim>& sys, const Decomposition<dim>& d) {
  auto& p = sys.particles;
  GRANPACK_CHECK(p.n_ghost() == 0, "migrate() needs the ghosts cleared");
  const int nranks = d.size();

  // Which grains leave, and where to.
  std::vector<std::vector<double>> out(nranks);
  std::vector<std::size_t> leaving;
  std::unordered_map<GlobalId, int> dest_of;  // leaving id -> destination
  for (std::size_t i = 0; i < p.n_owned(); ++i) {
    p.position[i] = Cell<dim>::wrap(p.position[i]);
    int owner = d.owner_of(p.position[i]);
    if (owner == d.rank()) continue;
    leaving.push_back(i);
    dest_of.emplace(p.id[i], owner);
  }
  // Message per destination: [n_particles, particles..., contacts...]
  std::vector<std::vector<std::size_t>> by_dest(nranks);
  for (std::size_t i : leaving) by_dest[dest_of[p.id[i]]].push_back(i);
  for (int r = 0; r < nranks; ++r) {
    if (by_dest[r].empty()) continue;
    out[r].push_back(static_cast<double>(by_dest[r].size()));
    for (std::size_t i : by_dest[r]) Packing<dim>::pack_particle(p, i, out[r]);
  }
  if (!dest_of.empty()) {
    for (std::size_t k = 0; k < sys.contacts.size(); ++k) {
      auto it = dest_of.find(sys.contacts.key(k).first);
      if (it == dest_of.end()) continue;
      Packing<dim>::pack_contact(sys.contacts.key(k), sys.contacts.state(k), out[it->second]);
    }
    sys.contacts.erase_if([&](const ContactKey& key, const ContactState<dim>&) {
      return dest_of.count(key.first) > 0;
    });
    p.remove_owned(leaving);
  }

  // All-to-all exchange. Simple and robust for any displacement; O(ranks) counts per call,
  // which is fine at the rank counts of this machine (neighbour-only exchange is an
  // optimisation for large rank counts, issue 8).
  std::vector<int> send_counts(nranks), recv_counts(nranks), sdispl(nranks, 0), rdispl(nranks, 0);
  for (int r = 0; r < nranks; ++r) send_counts[r] = static_cast<int>(out[r].size());
  MPI_Alltoall(send_counts.data(), 1, MPI_INT, recv_counts.data(), 1, MPI_INT, d.comm());
  std::vector<double> send_buf, recv_buf;
  for (int r = 0; r < nranks; ++r) {
    sdispl[r] = static_cast<int>(send_buf.size());
    send_buf.insert(send_buf.end(), out[r].begin(), out[r].end());
  }
  int total = 0;
  for (int r = 0; r < nranks; ++r) {
    rdispl[r] = total;
    total += recv_counts[r];
  }
  recv_buf.resize(static_cast<std::size_t>(total));
  MPI_Alltoallv(send_buf.data(), send_counts.data(), sdispl.data(), MPI_DOUBLE, recv_buf.data(),
                recv_counts.data(), rdispl.data(), MPI_DOUBLE, d.comm());

  for (int r = 0; r < nranks; ++r) {
    if (recv_counts[r] == 0) continue;
    const double* b = recv_buf.data() + rdispl[r];
    std::size_t pos = 0, end = static_cast<std::size_t>(recv_counts[r]);
    auto n = static_cast<std::size_t>(b[pos++]);
    for (std::size_t k = 0; k < n; ++k) p.add_owned(Packing<dim>::unpack_particle(b, pos));
    while (pos < end) {
      ContactKey key;
      ContactState<dim> s;
      Packing<dim>::unpack_contact(b, pos, key, s);
      sys.contacts.insert(key, s);
    }
  }
  return leaving.size();
}

template std::size_t migrate<2>(System<2>&, const Decomposition<2>&);
template std::size_t migrate<3>(System<3>&, const Decomposition<3>&);

}  // namespace granpack
