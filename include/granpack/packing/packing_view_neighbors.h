#pragma once
// for_each_neighbor (declared in packing_view.h): a cell-list sweep over one rank's grains.
#include "granpack/neighbor/cell_grid.h"

namespace granpack {

template <int dim, class F>
void for_each_neighbor(const PackingView<dim>& v, double cutoff, F&& f) {
  const auto& p = v.system.particles;
  CellGrid<dim> grid;
  grid.build(p, v.system.cell, cutoff);
  const double c2 = cutoff * cutoff;
  for (std::size_t i = 0; i < p.n_owned(); ++i) {
    const Vec<dim> ri = v.system.cell.to_real(p.position[i]);
    grid.for_each_neighbor_cell(grid.cell_of_particle(i), [&](std::size_t c) {
      for (std::size_t k = grid.cell_start(c); k < grid.cell_start(c + 1); ++k) {
        const std::size_t j = grid.order()[k];
        if (p.id[j] == p.id[i])
          continue;
        const Vec<dim> r = grid.sorted_position(k) - ri;
        const double d2 = r.squaredNorm();
        if (d2 < c2)
          f(i, j, r, std::sqrt(d2));
      }
    });
  }
}

} // namespace granpack
