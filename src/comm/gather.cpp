#include "granpack/comm/gather.h"

#include <algorithm>

#include "granpack/comm/particle_packing.h"

namespace granpack {

std::vector<double> gather_values(const std::vector<double>& mine, MPI_Comm comm, int root) {
  return gather_on_root(comm, mine, root);
}

template <int dim>
std::vector<Particle<dim>> gather_particles(const ParticleStore<dim>& p, MPI_Comm comm, int root) {
  std::vector<double> mine;
  mine.reserve(p.n_owned() * Packing<dim>::particle_size);
  for (std::size_t i = 0; i < p.n_owned(); ++i)
    Packing<dim>::pack_particle(p, i, mine);
  const std::vector<double> all = gather_values(mine, comm, root);
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  std::vector<Particle<dim>> out;
  if (rank != root)
    return out;
  std::size_t pos = 0;
  while (pos < all.size())
    out.push_back(Packing<dim>::unpack_particle(all.data(), pos));
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.id < b.id; });
  return out;
}

template std::vector<Particle<2>> gather_particles<2>(const ParticleStore<2>&, MPI_Comm, int);
template std::vector<Particle<3>> gather_particles<3>(const ParticleStore<3>&, MPI_Comm, int);

} // namespace granpack
