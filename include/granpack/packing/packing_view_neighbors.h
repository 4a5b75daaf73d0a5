#pragma once
// for_each_neighbor (declared in packing_view.h): a cell-list sweep over one rank's grains.
#include "granpack/neighbor/cell_grid.h"

namespace granpack {

template <int dim, class F>
void for_each_neighbor(const PackingView<dim>& v, double cutoff, F&& f) {
  CellGrid<dim> grid;
  grid.build(v.system.particles, v.system.cell, cutoff);
  for_each_owned_neighbor(grid, v.system.particles, v.system.cell, cutoff, f);
}

} // namespace granpack
