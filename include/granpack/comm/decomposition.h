#pragma once
// Spatial domain decomposition of the scaled cell [0,1)^dim on an MPI Cartesian grid.
// Working in scaled coordinates means the sub-boxes follow the cell when its lengths change.
#include <mpi.h>

#include <array>

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
  /// True when the scaled position (in [0,1)^dim) lies in this rank's sub-box.
  bool owns(const Vec<dim>& s) const { return owner_of(s) == rank_; }
  /// Rank of the sub-box holding scaled position s (in [0,1)^dim).
  int owner_of(const Vec<dim>& s) const;

private:
  void create_grid(MPI_Comm world);

  MPI_Comm cart_ = MPI_COMM_NULL;
  int rank_ = 0, size_ = 1;
  std::array<int, dim> dims_{}, coords_{};
  Vec<dim> lo_, hi_;
};

extern template class Decomposition<2>;
extern template class Decomposition<3>;

} // namespace granpack
