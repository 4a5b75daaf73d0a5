#include "granpack/comm/decomposition.h"

#include <algorithm>
#include <numeric>

#include "granpack/core/cut_planes.h"
#include "granpack/core/error.h"

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
  for (int a = 0; a < dim; ++a)
    cuts_[a] = uniform_cuts(dims_[a]);
  uniform_ = true;
  update_box();
}

template <int dim> void Decomposition<dim>::update_box() {
  for (int a = 0; a < dim; ++a) {
    lo_[a] = cuts_[a][coords_[a]];
    hi_[a] = cuts_[a][coords_[a] + 1];
  }
}

template <int dim>
void Decomposition<dim>::set_cuts(const std::array<std::vector<double>, dim>& cuts) {
  bool uniform = true;
  for (int a = 0; a < dim; ++a) {
    const auto& c = cuts[a];
    GRANPACK_CHECK(c.size() == static_cast<std::size_t>(dims_[a]) + 1 && c.front() == 0.0 &&
                       c.back() == 1.0 && std::is_sorted(c.begin(), c.end()) &&
                       std::adjacent_find(c.begin(), c.end()) == c.end(),
                   "axis " << a << ": " << c.size() << " cut planes for " << dims_[a]
                           << " slabs, or not increasing from 0 to 1");
    uniform = uniform && c == uniform_cuts(dims_[a]);
  }
  cuts_ = cuts;
  uniform_ = uniform;
  update_box();
}

template <int dim> double Decomposition<dim>::narrowest(int a) const {
  return narrowest_slab(cuts_[a]);
}

template <int dim> Decomposition<dim>::~Decomposition() {
  if (cart_ != MPI_COMM_NULL)
    MPI_Comm_free(&cart_);
}

template <int dim> int Decomposition<dim>::owner_of(const Vec<dim>& s) const {
  std::array<int, dim> c;
  for (int a = 0; a < dim; ++a) {
    if (uniform_) {
      // The static grid's expression, kept bit for bit (a grain on a plane stays with its rank).
      c[a] = std::clamp(static_cast<int>(s[a] * dims_[a]), 0, dims_[a] - 1);
    } else {
      // Slab k holds [c_k, c_k+1): the number of inner planes at or below s.
      const auto& k = cuts_[a];
      c[a] = static_cast<int>(std::upper_bound(k.begin() + 1, k.end() - 1, s[a]) - (k.begin() + 1));
    }
  }
  int r = 0;
  MPI_Cart_rank(cart_, c.data(), &r);
  return r;
}

template class Decomposition<2>;
template class Decomposition<3>;

} // namespace granpack
