#include "granpack/neighbor/cell_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "granpack/core/error.h"

namespace granpack {

namespace {
// At most this many cells per particle (plus a floor for tiny systems): a dilute gas gets
// larger cells rather than a grid that is mostly empty.
constexpr double kCellsPerParticle = 4.0;
constexpr double kMinCellBudget = 64.0;
// Cells are made this much larger than asked, so that two particles closer than min_side can
// never land two cells apart through the rounding of (r - lower) / side.
constexpr double kSideMargin = 1.0 + 1e-9;
} // namespace

template <int dim>
void CellGrid<dim>::build(const std::vector<Vec<dim>>& real_positions, double min_side) {
  position_ = real_positions;
  setup(min_side);
}

template <int dim>
void CellGrid<dim>::build(const ParticleStore<dim>& p, const Cell<dim>& cell, double min_side) {
  position_.resize(p.size());
  for (std::size_t i = 0; i < p.size(); ++i)
    position_[i] = cell.to_real(p.position[i]);
  setup(min_side);
}

template <int dim> void CellGrid<dim>::setup(double min_side) {
  GRANPACK_CHECK(min_side > 0 && std::isfinite(min_side),
                 "CellGrid: the cell side must be positive and finite, got " << min_side);
  const double side = min_side * kSideMargin;

  const std::size_t n = position_.size();
  GRANPACK_CHECK(n < std::numeric_limits<std::uint32_t>::max(),
                 "CellGrid: too many particles on one rank (" << n << ")");
  Vec<dim> lo = Vec<dim>::Zero(), hi = Vec<dim>::Zero();
  if (n > 0) {
    lo = hi = position_[0];
    for (const auto& r : position_) {
      GRANPACK_CHECK(r.allFinite(), "CellGrid: non-finite particle position " << r.transpose());
      lo = lo.cwiseMin(r);
      hi = hi.cwiseMax(r);
    }
  }
  // Cells per axis: as many cells of side >= `side` as fit in the extent, then capped.
  std::array<double, dim> nd;
  double total = 1.0;
  for (int a = 0; a < dim; ++a) {
    nd[a] = std::max(1.0, std::floor((hi[a] - lo[a]) / side));
    nd[a] = std::min(nd[a], 1e6);
    total *= nd[a];
  }
  const double budget = std::max(kMinCellBudget, kCellsPerParticle * static_cast<double>(n));
  if (total > budget) {
    const double f = std::pow(total / budget, 1.0 / dim);
    for (int a = 0; a < dim; ++a)
      nd[a] = std::max(1.0, std::floor(nd[a] / f));
  }
  lower_ = lo;
  for (int a = 0; a < dim; ++a) {
    dims_[a] = static_cast<int>(nd[a]);
    side_[a] = std::max(side, (hi[a] - lo[a]) / nd[a]);
    inv_side_[a] = 1.0 / side_[a];
  }
  bin();
}

template <int dim> void CellGrid<dim>::bin() {
  const std::size_t n = position_.size();
  std::size_t nc = 1;
  for (int a = 0; a < dim; ++a)
    nc *= static_cast<std::size_t>(dims_[a]);

  // Counting sort: count per cell, exclusive scan, scatter (stable: ascending index in a cell).
  cell_of_.resize(n);
  cell_start_.assign(nc + 1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    cell_of_[i] = cell_of(position_[i]);
    ++cell_start_[cell_of_[i] + 1];
  }
  for (std::size_t c = 0; c < nc; ++c)
    cell_start_[c + 1] += cell_start_[c];
  order_.resize(n);
  sorted_position_.resize(n);
  std::vector<std::size_t> fill(cell_start_.begin(), cell_start_.end() - 1);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t k = fill[cell_of_[i]]++;
    order_[k] = static_cast<std::uint32_t>(i);
    sorted_position_[k] = position_[i];
  }
}

template class CellGrid<2>;
template class CellGrid<3>;

} // namespace granpack
