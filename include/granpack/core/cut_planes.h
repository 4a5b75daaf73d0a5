#pragma once
// Where to cut one axis of the scaled cell [0,1) into slabs, for the domain decomposition: the
// uniform cuts of a static grid, or cuts at the quantiles of the grains' distribution along the
// axis (load balancing, docs/performance.md "Load balance"). MPI-free: the caller sums the
// histogram over the ranks.
#include <cstdint>
#include <span>
#include <vector>

namespace granpack {

/// slabs + 1 cut positions k / slabs, k = 0..slabs (c_0 = 0, c_slabs = 1).
std::vector<double> uniform_cuts(int slabs);

/// slabs + 1 cut positions c_0 = 0 < c_1 < ... < c_slabs = 1 that give each slab an equal share
/// of `histogram` (counts in equal bins of [0,1); the weight is spread evenly inside a bin), then
/// moved as little as needed for every slab to be at least min_width wide. A function of the
/// histogram alone (not of earlier cuts), so a restarted run that recomputes them gets the same
/// bits. An empty histogram gives uniform cuts. Needs slabs * min_width <= 1.
std::vector<double> quantile_cuts(std::span<const std::int64_t> histogram, int slabs,
                                  double min_width);

/// slabs + 1 cut positions on the bin edges of a histogram h[bin * columns + column] (bins
/// along the axis, columns: the cells of the other axes' slabs) that minimise the largest count
/// of a cell (one slab x one column), every slab at least min_width wide. With one column this
/// is the balanced partition of the axis; with several it balances the cells, where quantiles
/// of the axis' total only balance the slabs (a cluster in one corner of a 4 x 4 grid). The
/// smallest bound on a cell that greedy slabs reach (binary search on the bound; the exact
/// minimum over bin-edge cuts when no width limit binds). Needs slabs * min_width <= 1.
std::vector<double> minmax_cuts(std::span<const std::int64_t> histogram, std::size_t columns,
                                int slabs, double min_width);

/// The narrowest slab of `cuts`.
double narrowest_slab(std::span<const double> cuts);

} // namespace granpack
