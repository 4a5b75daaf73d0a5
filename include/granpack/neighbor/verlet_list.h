#pragma once
// Verlet (neighbour) list with a skin, in compressed sparse rows: for each OWNED particle i,
// neighbors(i) lists the local indices j (owned or ghost, ascending) it may interact with.
// Built with a CellGrid in O(n). MPI-free; see docs/neighbor.md.
//
// Which pairs (pair ownership). A pair of grains (a, b) is computed by exactly one rank, once:
// the rank that owns the grain with the smaller global id. So (i, j) is listed iff i is owned
// (i < n_owned), id[i] < id[j], and |r_ij| < cutoff_ij with r_ij = L (s_j - s_i) taken
// directly (ghosts carry the scaled position of the image this rank sees: no minimum image),
//   cutoff_ij = R_i + R_j + range + skin,
// where `range` is the contact law's extra interaction range (cohesion; 0 for plain contact)
// and `skin` is absolute (m). A grain and its own periodic image have the same id and are
// never paired. Two images of one grain cannot both be within cutoff of a third grain when
// every L_alpha > 2 * (largest cutoff); build() checks that, so each physical pair is listed
// at most once. (The check uses the local largest cutoff; it may fail on one rank only.)
//
// Rebuild criterion, valid while the cell changes size. At build time we store s_i,b and L_b.
// Now (L, s_i): let d_i = |L (s_i - s_i,b)| (displacement measured at the current cell) and
// e = max_alpha max(0, 1 - L_alpha / L_b,alpha) (the largest compressive strain of the cell).
// For a pair NOT in the list, |r_ij,b| >= cutoff_ij = c_ij + skin (c_ij = R_i + R_j + range).
// Its current separation is
//   r_ij = L Ds = L (Ds - Ds_b) + diag(L / L_b) r_ij,b,   Ds = s_j - s_i,
//   |r_ij| >= (1 - e) |r_ij,b| - d_i - d_j >= (1 - e)(c_ij + skin) - 2 max_k d_k,
// (|diag(L/L_b) x| >= min_alpha(L_alpha/L_b,alpha) |x| >= (1 - e)|x|; growth of the cell only
// separates pairs). It stays >= c_ij (no missed interaction) as long as
//   2 max_k d_k + e * (c_ij + skin) <= skin,
// so needs_rebuild() returns true when 2 max_k d_k + e * max_cutoff > skin, max_cutoff being
// the largest cutoff_ij at build time. All local particles are checked (ghost positions are
// refreshed by the comm layer with the same local indices until the next rebuild). The verdict
// is local: the caller all-reduces it (any rank true => every rank rebuilds). A change in the
// number of owned or local particles (migration) also means "rebuild"; so does a scaled position
// wrapped by +-1 without a rebuild (it shows as a displacement of L_alpha).
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "granpack/core/cell.h"
#include "granpack/core/particles.h"
#include "granpack/core/vec.h"
#include "granpack/neighbor/cell_grid.h"

namespace granpack {

struct NeighborParams {
  double skin = 0;  ///< absolute skin (m), >= 0
  double range = 0; ///< extra interaction range of the contact law (m), >= 0
};

template <int dim> class VerletList {
public:
  /// Builds the list for the local particles of `p` (owned then ghosts) in `cell`. Remembers
  /// the positions and cell lengths for needs_rebuild(). Throws granpack::Error if some
  /// L_alpha <= 2 * max_cutoff() or a position is not finite.
  void build(const ParticleStore<dim>& p, const Cell<dim>& cell, const NeighborParams& prm);

  /// Local verdict of the rebuild criterion (header comment); true if never built.
  bool needs_rebuild(const ParticleStore<dim>& p, const Cell<dim>& cell) const;
  /// The left-hand side of the criterion, 2 max_i d_i + e * max_cutoff (m): needs_rebuild() is
  /// true when it exceeds the skin. Infinite if the particle counts changed or never built.
  double drift(const ParticleStore<dim>& p, const Cell<dim>& cell) const;

  bool built() const { return built_; }
  std::size_t n_owned() const { return offsets_.empty() ? 0 : offsets_.size() - 1; }
  std::size_t n_pairs() const { return neighbors_.size(); }
  /// Largest cutoff_ij = R_i + R_j + range + skin over local grains at the last build (m).
  double max_cutoff() const { return max_cutoff_; }
  const NeighborParams& params() const { return params_; }

  /// Neighbours j of owned particle i: local indices, ascending, id[j] > id[i].
  std::span<const std::uint32_t> neighbors(std::size_t i) const {
    return {neighbors_.data() + offsets_[i], neighbors_.data() + offsets_[i + 1]};
  }
  const std::uint32_t* begin(std::size_t i) const { return neighbors_.data() + offsets_[i]; }
  const std::uint32_t* end(std::size_t i) const { return neighbors_.data() + offsets_[i + 1]; }
  /// CSR arrays: neighbours of i are neighbor_array()[offsets()[i] .. offsets()[i + 1]).
  const std::vector<std::size_t>& offsets() const { return offsets_; }
  const std::vector<std::uint32_t>& neighbor_array() const { return neighbors_; }

  /// Keeps only the pairs (i, j) with keep(i, j) true, in their order (a frozen contact
  /// network lists the pairs of its initial contacts only). Pairs left out never interact
  /// until the next build, so the rebuild criterion stays valid.
  template <class Keep> void retain_pairs(Keep&& keep) {
    const std::size_t n = n_owned();
    std::size_t w = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t first = offsets_[i], last = offsets_[i + 1];
      offsets_[i] = w;
      for (std::size_t k = first; k < last; ++k)
        if (keep(i, static_cast<std::size_t>(neighbors_[k])))
          neighbors_[w++] = neighbors_[k];
    }
    offsets_[n] = w;
    neighbors_.resize(w);
  }

  /// Calls f(i, j) for every listed pair, i owned in ascending order, j ascending.
  template <class F> void for_each_pair(F&& f) const {
    const std::size_t n = n_owned();
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t k = offsets_[i]; k < offsets_[i + 1]; ++k)
        f(i, static_cast<std::size_t>(neighbors_[k]));
  }

private:
  NeighborParams params_{};
  bool built_ = false;
  double max_cutoff_ = 0;
  std::size_t n_owned_b_ = 0;
  std::vector<Vec<dim>> position_b_; // scaled positions at build time (all local particles)
  Vec<dim> length_b_ = Vec<dim>::Ones();

  std::vector<std::size_t> offsets_; // n_owned + 1
  std::vector<std::uint32_t> neighbors_;

  // scratch kept between builds to avoid reallocations
  CellGrid<dim> grid_;
  std::vector<double> sorted_radius_;
  std::vector<GlobalId> sorted_id_;
  std::vector<std::uint32_t> tmp_; // neighbours in cell-sweep order
  std::vector<std::size_t> tmp_start_, tmp_count_;
};

extern template class VerletList<2>;
extern template class VerletList<3>;

} // namespace granpack
