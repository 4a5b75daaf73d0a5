#include "granpack/comm/gather.h"

#include <algorithm>

#include "granpack/comm/particle_packing.h"

namespace granpack {

std::vector<double> gather_values(const std::vector<double>& mine, MPI_Comm comm, int root) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  const int count = static_cast<int>(mine.size());
  std::vector<int> counts(rank == root ? std::size_t(size) : 0), displs(counts.size());
  MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, root, comm);
  std::vector<double> all;
  if (rank == root) {
    int total = 0;
    for (std::size_t r = 0; r < counts.size(); ++r) displs[r] = total, total += counts[r];
    all.resize(static_cast<std::size_t>(total));
  }
  MPI_Gatherv(mine.data(), count, MPI_DOUBLE, all.data(), counts.data(), displs.data(), MPI_DOUBLE,
              root, comm);
  return all;
}

template <int dim>
std::vector<Particle<dim>> gather_particles(const ParticleStore<dim>& p, MPI_Comm comm, int root) {
  std::vector<double> mine;
  mine.reserve(p.n_owned() * Packing<dim>::particle_size);
  for (std::size_t i = 0; i < p.n_owned(); ++i) Packing<dim>::pack_particle(p, i, mine);
  const std::vector<double> all = gather_values(mine, comm, root);
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  std::vector<Particle<dim>> out;
  if (rank != root) return out;
  std::size_t pos = 0;
  while (pos < all.size()) out.push_back(Packing<dim>::unpack_particle(all.data(), pos));
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.id < b.id; });
  return out;
}

template std::vector<Particle<2>> gather_particles<2>(const ParticleStore<2>&, MPI_Comm, int);
template std::vector<Particle<3>> gather_particles<3>(const ParticleStore<3>&, MPI_Comm, int);

}  // namespace granpack
