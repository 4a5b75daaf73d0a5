#include "granpack/neighbor/verlet_list.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "granpack/core/error.h"

namespace granpack {

template <int dim>
void VerletList<dim>::build(const ParticleStore<dim>& p, const Cell<dim>& cell,
                            const NeighborParams& prm) {
  GRANPACK_CHECK(prm.skin >= 0 && std::isfinite(prm.skin),
                 "VerletList: the skin must be >= 0, got " << prm.skin);
  GRANPACK_CHECK(prm.range >= 0 && std::isfinite(prm.range),
                 "VerletList: the interaction range must be >= 0, got " << prm.range);
  params_ = prm;
  built_ = false;
  const std::size_t n = p.size();
  const std::size_t no = p.n_owned();

  double r_max = 0;
  for (std::size_t i = 0; i < n; ++i)
    r_max = std::max(r_max, p.radius[i]);
  max_cutoff_ = 2 * r_max + prm.range + prm.skin;
  for (int a = 0; a < dim; ++a)
    GRANPACK_CHECK(cell.length[a] > 2 * max_cutoff_,
                   "VerletList: the cell length L_"
                       << a << " = " << cell.length[a]
                       << " must exceed twice the largest cutoff 2 x " << max_cutoff_
                       << " (2 R_max + range + skin), or a grain would meet its own image");

  offsets_.assign(no + 1, 0);
  neighbors_.clear();
  if (n > 0 && max_cutoff_ > 0) {
    grid_.build(p, cell, max_cutoff_);
    const auto& order = grid_.order();
    sorted_radius_.resize(n);
    sorted_id_.resize(n);
    for (std::size_t k = 0; k < n; ++k) {
      sorted_radius_[k] = p.radius[order[k]];
      sorted_id_[k] = p.id[order[k]];
    }
    // Sweep the owned particles in cell order (neighbour data stays in cache), writing each
    // one's neighbours to a contiguous segment of tmp_; then lay the segments out by index.
    tmp_.clear();
    tmp_start_.assign(no, 0);
    tmp_count_.assign(no, 0);
    const double extra = prm.range + prm.skin;
    for (std::size_t c = 0; c < grid_.n_cells(); ++c) {
      for (std::size_t k = grid_.cell_start(c); k < grid_.cell_start(c + 1); ++k) {
        const std::uint32_t i = order[k];
        if (i >= no)
          continue;
        const GlobalId id_i = sorted_id_[k];
        const double ri = sorted_radius_[k] + extra;
        const Vec<dim> xi = grid_.sorted_position(k);
        const std::size_t start = tmp_.size();
        grid_.for_each_neighbor_cell(c, [&](std::size_t c2) {
          for (std::size_t k2 = grid_.cell_start(c2); k2 < grid_.cell_start(c2 + 1); ++k2) {
            if (sorted_id_[k2] <= id_i)
              continue; // smaller id owns; same id = own image
            const double cut = ri + sorted_radius_[k2];
            if ((grid_.sorted_position(k2) - xi).squaredNorm() < cut * cut)
              tmp_.push_back(order[k2]);
          }
        });
        std::sort(tmp_.begin() + static_cast<std::ptrdiff_t>(start), tmp_.end());
        tmp_start_[i] = start;
        tmp_count_[i] = tmp_.size() - start;
      }
    }
    for (std::size_t i = 0; i < no; ++i)
      offsets_[i + 1] = offsets_[i] + tmp_count_[i];
    neighbors_.resize(offsets_[no]);
    for (std::size_t i = 0; i < no; ++i)
      std::copy_n(tmp_.begin() + static_cast<std::ptrdiff_t>(tmp_start_[i]), tmp_count_[i],
                  neighbors_.begin() + static_cast<std::ptrdiff_t>(offsets_[i]));
  }

  n_owned_b_ = no;
  position_b_ = p.position;
  length_b_ = cell.length;
  built_ = true;
}

template <int dim>
double VerletList<dim>::drift(const ParticleStore<dim>& p, const Cell<dim>& cell) const {
  constexpr double inf = std::numeric_limits<double>::infinity();
  if (!built_ || p.n_owned() != n_owned_b_ || p.size() != position_b_.size())
    return inf;
  double d2 = 0;
  for (std::size_t i = 0; i < position_b_.size(); ++i) {
    const double x = cell.length.cwiseProduct(p.position[i] - position_b_[i]).squaredNorm();
    if (!std::isfinite(x))
      return inf; // a lost grain: rebuild (and let the build complain)
    d2 = std::max(d2, x);
  }
  double e = 0; // largest compressive strain since the build
  for (int a = 0; a < dim; ++a)
    e = std::max(e, 1.0 - cell.length[a] / length_b_[a]);
  return 2 * std::sqrt(d2) + e * max_cutoff_;
}

template <int dim>
bool VerletList<dim>::needs_rebuild(const ParticleStore<dim>& p, const Cell<dim>& cell) const {
  return !(drift(p, cell) <= params_.skin);
}

template class VerletList<2>;
template class VerletList<3>;

} // namespace granpack
