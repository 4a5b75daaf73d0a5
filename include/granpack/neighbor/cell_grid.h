#pragma once
// Cell grid (cell list) for the neighbour search: bins particles into cells of side >= a given
// length over the REAL-space bounding box of the particles a rank holds (its sub-box plus the
// ghost layer). It is not periodic: periodic images are explicit ghosts whose scaled positions
// are already shifted by +-1, so the grid only ever sees direct real positions r = L.s.
//
// Bins are built by a counting sort (compressed sparse rows): `cell_start(c)..cell_start(c+1)`
// indexes `order()`, the particle indices sorted by cell, and `sorted_position(k)` holds the
// real position of particle order()[k]. No per-cell containers; two passes over the particles,
// one over the cells: O(n + n_cells). The number of cells is capped at a few per particle, so
// a sparse gas does not allocate a huge empty grid (cells then get larger than asked).
//
// MPI-free. Errors (a non-finite position) throw granpack::Error on the rank that sees them; a
// caller in a collective phase wraps the build (comm/collective_error.h).
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "granpack/core/cell.h"
#include "granpack/core/particles.h"
#include "granpack/core/vec.h"

namespace granpack {

template <int dim> class CellGrid {
public:
  using Index = std::array<int, dim>; ///< integer cell coordinates

  /// Bins the given real positions into cells of side >= min_side (> 0).
  void build(const std::vector<Vec<dim>>& real_positions, double min_side);
  /// Bins every local particle (owned and ghosts) of `p` at r = L.s.
  void build(const ParticleStore<dim>& p, const Cell<dim>& cell, double min_side);

  std::size_t n_particles() const { return order_.size(); }
  std::size_t n_cells() const { return cell_start_.empty() ? 0 : cell_start_.size() - 1; }
  const Index& dims() const { return dims_; }      ///< cells per axis (>= 1 each)
  const Vec<dim>& lower() const { return lower_; } ///< corner of the grid (real units)
  const Vec<dim>& side() const { return side_; }   ///< cell side per axis, >= min_side

  /// Cell coordinates of a real position (clamped into the grid).
  Index coords_of(const Vec<dim>& r) const {
    Index c;
    for (int a = 0; a < dim; ++a) {
      const double x = (r[a] - lower_[a]) * inv_side_[a];
      int k =
          x <= 0.0 ? 0 : (x >= static_cast<double>(dims_[a]) ? dims_[a] - 1 : static_cast<int>(x));
      c[a] = k;
    }
    return c;
  }
  /// Flat (row-major, last axis fastest) index of cell coordinates inside the grid.
  std::size_t flat(const Index& c) const {
    std::size_t f = 0;
    for (int a = 0; a < dim; ++a)
      f = f * static_cast<std::size_t>(dims_[a]) + static_cast<std::size_t>(c[a]);
    return f;
  }
  std::size_t cell_of(const Vec<dim>& r) const { return flat(coords_of(r)); }

  /// Sorted slot range of cell c: order()[cell_start(c) .. cell_start(c + 1)).
  std::size_t cell_start(std::size_t c) const { return cell_start_[c]; }
  /// Particle indices sorted by cell (stable within a cell: ascending index).
  const std::vector<std::uint32_t>& order() const { return order_; }
  /// Real position of particle order()[k], stored in cell order for cache-friendly sweeps.
  const Vec<dim>& sorted_position(std::size_t k) const { return sorted_position_[k]; }
  /// Cell of particle i (original index).
  std::size_t cell_of_particle(std::size_t i) const { return cell_of_[i]; }

  /// Calls f(c2) for every cell c2 of the 3^dim block around cell c (clipped at the grid
  /// edges), c itself included. Any two particles closer than min_side are in such cells.
  template <class F> void for_each_neighbor_cell(std::size_t c, F&& f) const {
    Index ci;
    std::size_t rest = c;
    for (int a = dim - 1; a >= 0; --a) {
      ci[a] = static_cast<int>(rest % static_cast<std::size_t>(dims_[a]));
      rest /= static_cast<std::size_t>(dims_[a]);
    }
    Index lo, hi;
    for (int a = 0; a < dim; ++a) {
      lo[a] = ci[a] > 0 ? ci[a] - 1 : 0;
      hi[a] = ci[a] + 1 < dims_[a] ? ci[a] + 1 : dims_[a] - 1;
    }
    Index k = lo;
    while (true) {
      f(flat(k));
      int a = dim - 1;
      while (a >= 0 && k[a] == hi[a]) {
        k[a] = lo[a];
        --a;
      }
      if (a < 0)
        break;
      ++k[a];
    }
  }

private:
  void setup(double min_side); // sizes the grid over position_, then bin()
  void bin();

  Index dims_{};
  Vec<dim> lower_ = Vec<dim>::Zero(), side_ = Vec<dim>::Ones(), inv_side_ = Vec<dim>::Ones();
  std::vector<Vec<dim>> position_;        // real positions, original order
  std::vector<Vec<dim>> sorted_position_; // real positions, cell order
  std::vector<std::size_t> cell_start_;   // n_cells + 1 offsets into order_
  std::vector<std::uint32_t> order_;      // particle indices sorted by cell
  std::vector<std::size_t> cell_of_;      // flat cell of each particle (original order)
};

extern template class CellGrid<2>;
extern template class CellGrid<3>;

/// Calls f(i, j, r_ij, |r_ij|) for every owned particle i of `p` and every local particle j
/// (owned or ghost, not an image of i itself) with |r_ij| < cutoff, r_ij the real vector from
/// i to j. The grid is built over `p` with cells of side >= cutoff. Ghosts stand for the
/// periodic images: the grid itself does not wrap.
template <int dim, class F>
void for_each_owned_neighbor(const CellGrid<dim>& grid, const ParticleStore<dim>& p,
                             const Cell<dim>& cell, double cutoff, F&& f) {
  const double c2 = cutoff * cutoff;
  for (std::size_t i = 0; i < p.n_owned(); ++i) {
    const Vec<dim> ri = cell.to_real(p.position[i]);
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
