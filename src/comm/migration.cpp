#include "granpack/comm/migration.h"

#include <mpi.h>

#include <unordered_map>

#include "granpack/comm/particle_packing.h"
#include "granpack/core/error.h"

namespace granpack {

namespace {
/// MPI_Alltoallv of double buffers, one per destination rank.
std::vector<std::vector<double>> exchange(MPI_Comm comm,
                                          const std::vector<std::vector<double>>& out) {
  const int n = static_cast<int>(out.size());
  std::vector<int> sc(n), rc(n), sd(n, 0), rd(n, 0);
  std::vector<double> sbuf;
  for (int r = 0; r < n; ++r) {
    sc[r] = static_cast<int>(out[r].size());
    sd[r] = static_cast<int>(sbuf.size());
    sbuf.insert(sbuf.end(), out[r].begin(), out[r].end());
  }
  MPI_Alltoall(sc.data(), 1, MPI_INT, rc.data(), 1, MPI_INT, comm);
  int total = 0;
  for (int r = 0; r < n; ++r)
    rd[r] = total, total += rc[r];
  std::vector<double> rbuf(static_cast<std::size_t>(total));
  MPI_Alltoallv(sbuf.data(), sc.data(), sd.data(), MPI_DOUBLE, rbuf.data(), rc.data(), rd.data(),
                MPI_DOUBLE, comm);
  std::vector<std::vector<double>> in(n);
  for (int r = 0; r < n; ++r)
    in[r].assign(rbuf.begin() + rd[r], rbuf.begin() + rd[r] + rc[r]);
  return in;
}
} // namespace

template <int dim> std::size_t migrate(System<dim>& sys, const Decomposition<dim>& d) {
  auto& p = sys.particles;
  GRANPACK_CHECK(p.n_ghost() == 0, "migrate() needs the ghosts cleared");
  const int nranks = d.size();

  // Which grains leave, and where to.
  std::vector<std::vector<double>> out(nranks);
  std::vector<std::size_t> leaving;
  std::unordered_map<GlobalId, int> dest_of; // leaving id -> destination
  for (std::size_t i = 0; i < p.n_owned(); ++i) {
    p.position[i] = Cell<dim>::wrap(p.position[i]);
    int owner = d.owner_of(p.position[i]);
    if (owner == d.rank())
      continue;
    leaving.push_back(i);
    dest_of.emplace(p.id[i], owner);
  }
  // Message per destination: [n_particles, particles..., contacts...]
  std::vector<std::vector<std::size_t>> by_dest(nranks);
  for (std::size_t i : leaving)
    by_dest[dest_of[p.id[i]]].push_back(i);
  for (int r = 0; r < nranks; ++r) {
    if (by_dest[r].empty())
      continue;
    out[r].push_back(static_cast<double>(by_dest[r].size()));
    for (std::size_t i : by_dest[r])
      Packing<dim>::pack_particle(p, i, out[r]);
  }
  if (!dest_of.empty()) {
    for (std::size_t k = 0; k < sys.contacts.size(); ++k) {
      auto it = dest_of.find(sys.contacts.key(k).first);
      if (it == dest_of.end())
        continue;
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
  const auto in = exchange(d.comm(), out);
  for (int r = 0; r < nranks; ++r) {
    if (in[r].empty())
      continue;
    const double* b = in[r].data();
    std::size_t pos = 0, end = in[r].size();
    auto n = static_cast<std::size_t>(b[pos++]);
    for (std::size_t k = 0; k < n; ++k)
      p.add_owned(Packing<dim>::unpack_particle(b, pos));
    while (pos < end) {
      ContactKey key;
      ContactState<dim> s;
      Packing<dim>::unpack_contact(b, pos, key, s);
      sys.contacts.insert(key, s);
    }
  }
  return leaving.size();
}

template <int dim> void distribute(System<dim>& sys, const Decomposition<dim>& d) {
  migrate(sys, d);
  const int nranks = d.size();
  auto directory_of = [&](GlobalId id) { return static_cast<int>(id % nranks); };
  // 1. Each grain's owner is registered at its directory rank.
  std::vector<std::vector<double>> out(nranks);
  for (std::size_t i = 0; i < sys.particles.n_owned(); ++i)
    out[directory_of(sys.particles.id[i])].push_back(static_cast<double>(sys.particles.id[i]));
  auto reg = exchange(d.comm(), out);
  std::unordered_map<GlobalId, int> owner;
  for (int r = 0; r < nranks; ++r)
    for (double id : reg[r])
      owner.emplace(static_cast<GlobalId>(id), r);
  // 2. Contacts go to the directory rank of their first grain, 3. which forwards them.
  for (auto& o : out)
    o.clear();
  for (std::size_t k = 0; k < sys.contacts.size(); ++k)
    Packing<dim>::pack_contact(sys.contacts.key(k), sys.contacts.state(k),
                               out[directory_of(sys.contacts.key(k).first)]);
  sys.contacts.clear();
  auto at_directory = exchange(d.comm(), out);
  for (auto& o : out)
    o.clear();
  std::int64_t orphans = 0;
  for (int r = 0; r < nranks; ++r) {
    std::size_t pos = 0;
    while (pos < at_directory[r].size()) {
      ContactKey key;
      ContactState<dim> s;
      Packing<dim>::unpack_contact(at_directory[r].data(), pos, key, s);
      auto it = owner.find(key.first);
      if (it == owner.end()) {
        ++orphans;
        continue;
      }
      Packing<dim>::pack_contact(key, s, out[it->second]);
    }
  }
  auto mine = exchange(d.comm(), out);
  for (int r = 0; r < nranks; ++r) {
    std::size_t pos = 0;
    while (pos < mine[r].size()) {
      ContactKey key;
      ContactState<dim> s;
      Packing<dim>::unpack_contact(mine[r].data(), pos, key, s);
      sys.contacts.insert(key, s);
    }
  }
  std::int64_t total = 0;
  MPI_Allreduce(&orphans, &total, 1, MPI_INT64_T, MPI_SUM, d.comm());
  GRANPACK_CHECK(total == 0, total << " contacts name a first grain that does not exist");
}

template void distribute<2>(System<2>&, const Decomposition<2>&);
template void distribute<3>(System<3>&, const Decomposition<3>&);
template std::size_t migrate<2>(System<2>&, const Decomposition<2>&);
template std::size_t migrate<3>(System<3>&, const Decomposition<3>&);

} // namespace granpack
