#pragma once
// Spatial domain decomposition of the scaled cell [0,1)^dim on an MPI Cartesian grid.
// Working in scaled coordinates means the sub-boxes follow the cell when its lengths change.
// Each axis is cut into dims[a] slabs by planes that are uniform (a static grid) or placed by
// the load balancer (comm/rebalance.h); the planes of an axis are the same across the grid, so
// every rank keeps the same face neighbours and the halo stays a Cartesian shift.
#include <mpi.h>

#include <array>
#include <vector>

#include "granpack/core/vec.h"

namespace granpack {

template <int dim> class Decomposition {
public:
  /// Collective on `world`. The grid has as many ranks along an axis as the cell lengths
  /// suggest (longer axes are cut more), chosen by MPI_Dims_create among the factorisations.
  Decomposition(MPI_Comm world, const Vec<dim>& cell_lengths);
  /// Collective on `world`: a given grid (a restart on the checkpoint's rank count must cut
  /// the cell as the interrupted run did, whatever the cell's shape now). prod(dims) = ranks.
  Decomposition(MPI_Comm world, const std::array<int, dim>& dims);
  ~Decomposition();
  Decomposition(const Decomposition&) = delete;
  Decomposition& operator=(const Decomposition&) = delete;

  MPI_Comm comm() const { return cart_; }
  int rank() const { return rank_; }
  int size() const { return size_; }
  const std::array<int, dim>& dims() const { return dims_; }
  const std::array<int, dim>& coords() const { return coords_; }
  /// This rank's sub-box [lo, hi) in scaled coordinates.
  const Vec<dim>& lo() const { return lo_; }
  const Vec<dim>& hi() const { return hi_; }
  /// The cut planes of axis a: dims()[a] + 1 positions from 0 to 1 (slab k is [c_k, c_k+1)).
  const std::vector<double>& cuts(int a) const { return cuts_[a]; }
  /// True while every axis is cut uniformly (the static grid).
  bool uniform() const { return uniform_; }
  /// Moves the cut planes (the same on every rank; the grains follow at the next migration).
  /// Each axis needs dims()[a] + 1 increasing positions from 0 to 1.
  void set_cuts(const std::array<std::vector<double>, dim>& cuts);
  /// The narrowest slab along axis a, as a fraction of the cell length (the same on every rank).
  double narrowest(int a) const;
  /// True when the scaled position (in [0,1)^dim) lies in this rank's sub-box.
  bool owns(const Vec<dim>& s) const { return owner_of(s) == rank_; }
  /// Rank of the sub-box holding scaled position s (in [0,1)^dim).
  int owner_of(const Vec<dim>& s) const;

private:
  void create_grid(MPI_Comm world);
  void update_box();

  MPI_Comm cart_ = MPI_COMM_NULL;
  int rank_ = 0, size_ = 1;
  std::array<int, dim> dims_{}, coords_{};
  Vec<dim> lo_, hi_;
  std::array<std::vector<double>, dim> cuts_;
  bool uniform_ = true;
};

extern template class Decomposition<2>;
extern template class Decomposition<3>;

} // namespace granpack
