#include "granpack/analysis/local_order.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numeric>

#include "granpack/neighbor/cell_grid.h"

namespace granpack {

template <int dim>
std::vector<GrainBonds<dim>> grain_bonds(const Cell<dim>& cell, const ParticleStore<dim>& p,
                                         double d_c) {
  CellGrid<dim> grid;
  grid.build(p, cell, d_c);
  std::vector<std::vector<std::pair<GlobalId, Vec<dim>>>> found(p.n_owned());
  for_each_owned_neighbor(grid, p, cell, d_c,
                          [&](std::size_t i, std::size_t j, const Vec<dim>& r, double) {
                            found[i].emplace_back(p.id[j], r);
                          });
  std::vector<GrainBonds<dim>> out(p.n_owned());
  for (std::size_t i = 0; i < p.n_owned(); ++i) {
    // Ascending id: the sums do not depend on how ranks and cells ordered the grains.
    std::sort(found[i].begin(), found[i].end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
    out[i].id = p.id[i];
    for (const auto& [id, r] : found[i]) {
      out[i].neighbor_ids.push_back(id);
      out[i].bonds.push_back(r);
    }
  }
  return out;
}

double psi6_modulus(std::span<const Vec<2>> bonds) {
  if (bonds.empty())
    return 0.0;
  std::complex<double> sum = 0;
  for (const auto& r : bonds)
    sum += std::polar(1.0, 6 * std::atan2(r[1], r[0]));
  return std::abs(sum) / double(bonds.size());
}

template std::vector<GrainBonds<2>> grain_bonds<2>(const Cell<2>&, const ParticleStore<2>&, double);
template std::vector<GrainBonds<3>> grain_bonds<3>(const Cell<3>&, const ParticleStore<3>&, double);

} // namespace granpack
