#include "granpack/comm/decomposition.h"

#include <algorithm>
#include <numeric>

namespace granpack {

template <int dim> Decomposition<dim>::Decomposition(MPI_Comm world, const Vec<dim>& cell_lengths) {
  int nranks = 1;
  MPI_Comm_size(world, &nranks);
  // MPI_Dims_create returns dims in non-increasing order; give the largest count to the
  // longest axis so that sub-boxes stay as cubic as possible.
  std::array<int, dim> d{};
  MPI_Dims_create(nranks, dim, d.data());
  std::array<int, dim> axes;
  std::iota(axes.begin(), axes.end(), 0);
  std::stable_sort(axes.begin(), axes.end(),
                   [&](int a, int b) { return cell_lengths[a] > cell_lengths[b]; });
  for (int k = 0; k < dim; ++k)
    dims_[axes[k]] = d[k];
  create_grid(world);
}

template <int dim>
Decomposition<dim>::Decomposition(MPI_Comm world, const std::array<int, dim>& dims) : dims_(dims) {
  create_grid(world);
}

template <int dim> void Decomposition<dim>::create_grid(MPI_Comm world) {
  std::array<int, dim> periods;
  periods.fill(1);
  // reorder = 0: rank numbers stay those of `world`, so logs and files speak of the same ranks.
  MPI_Cart_create(world, dim, dims_.data(), periods.data(), 0, &cart_);
  MPI_Comm_rank(cart_, &rank_);
  MPI_Comm_size(cart_, &size_);
  MPI_Cart_coords(cart_, rank_, dim, coords_.data());
  for (int a = 0; a < dim; ++a) {
    lo_[a] = double(coords_[a]) / dims_[a];
    hi_[a] = double(coords_[a] + 1) / dims_[a];
  }
}

template <int dim> Decomposition<dim>::~Decomposition() {
  if (cart_ != MPI_COMM_NULL)
    MPI_Comm_free(&cart_);
}

template <int dim> int Decomposition<dim>::owner_of(const Vec<dim>& s) const {
  std::array<int, dim> c;
  for (int a = 0; a < dim; ++a)
    c[a] = std::clamp(static_cast<int>(s[a] * dims_[a]), 0, dims_[a] - 1);
  int r = 0;
  MPI_Cart_rank(cart_, c.data(), &r);
  return r;
}

template class Decomposition<2>;
template class Decomposition<3>;

} // namespace granpack
