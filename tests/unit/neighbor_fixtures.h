#pragma once
// Test fixtures for the neighbour search: a random polydisperse periodic sample ("world") and
// the local view one rank of a domain decomposition would hold (owned grains in a scaled
// sub-box, ghosts = images within a real distance of the sub-box faces, periodic images and
// images of locally owned grains included), plus brute-force O(n^2) pair sets.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <random>
#include <set>
#include <tuple>
#include <type_traits>
#include <vector>

#include "granpack/core/cell.h"
#include "granpack/core/particles.h"
#include "granpack/neighbor/verlet_list.h"

namespace granpack::test {

using Dims = ::testing::Types<std::integral_constant<int, 2>, std::integral_constant<int, 3>>;

/// A physical pair: (smaller id, larger id, integer shift k) meaning r = L (s_b + k - s_a) with
/// s_a, s_b the positions of the grains in the world (not wrapped by the test's moves).
template <int dim> using PairKey = std::tuple<GlobalId, GlobalId, std::array<int, dim>>;

template <int dim> struct World {
  Cell<dim> cell;
  std::vector<GlobalId> id;
  std::vector<double> radius;
  std::vector<Vec<dim>> s; // scaled positions
  NeighborParams prm;

  double max_cutoff() const {
    return 2 * *std::max_element(radius.begin(), radius.end()) + prm.range + prm.skin;
  }
};

/// n grains, radii uniform in [r_min, r_max], positions uniform in the unit scaled cell,
/// ids a shuffled, non-contiguous set.
template <int dim>
World<dim> make_world(std::mt19937_64& rng, std::size_t n, const Vec<dim>& length, double r_min,
                      double r_max, NeighborParams prm) {
  World<dim> w;
  w.cell.length = length;
  w.prm = prm;
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<GlobalId> ids(n);
  std::iota(ids.begin(), ids.end(), GlobalId{0});
  std::shuffle(ids.begin(), ids.end(), rng);
  for (std::size_t g = 0; g < n; ++g) {
    w.id.push_back(3 * ids[g] + 7);
    w.radius.push_back(r_min + (r_max - r_min) * u(rng));
    Vec<dim> x;
    for (int a = 0; a < dim; ++a)
      x[a] = u(rng);
    w.s.push_back(x);
  }
  return w;
}

/// What one "rank" holds: the store plus, for each local index, its world grain and shift.
template <int dim> struct RankView {
  ParticleStore<dim> p;
  std::vector<std::size_t> grain;          // world index of local particle
  std::vector<std::array<int, dim>> shift; // image shift (0 for owned)

  /// Refreshes positions from the world (owned and ghosts, like forward communication).
  void refresh(const World<dim>& w) {
    for (std::size_t i = 0; i < p.size(); ++i) {
      Vec<dim> x = w.s[grain[i]];
      for (int a = 0; a < dim; ++a)
        x[a] += shift[i][a];
      p.position[i] = x;
    }
  }
};

/// Owned: grains with s in [lo, hi); ghosts: every image s + k (k in {-1,0,1}^dim, except an
/// owned grain itself) within real distance `width` of that box. Owned and ghosts are shuffled.
template <int dim>
RankView<dim> make_rank(std::mt19937_64& rng, const World<dim>& w, const Vec<dim>& lo,
                        const Vec<dim>& hi, double width) {
  RankView<dim> v;
  std::vector<std::size_t> owned, ghost_g;
  std::vector<std::array<int, dim>> ghost_k;
  auto inside = [&](const Vec<dim>& x) {
    for (int a = 0; a < dim; ++a)
      if (x[a] < lo[a] || x[a] >= hi[a])
        return false;
    return true;
  };
  for (std::size_t g = 0; g < w.s.size(); ++g) {
    const bool own = inside(w.s[g]);
    if (own)
      owned.push_back(g);
    const int n_img = dim == 2 ? 9 : 27;
    for (int m = 0; m < n_img; ++m) {
      std::array<int, dim> k;
      int rest = m;
      bool zero = true;
      for (int a = 0; a < dim; ++a) {
        k[a] = rest % 3 - 1;
        rest /= 3;
        zero = zero && k[a] == 0;
      }
      if (zero && own)
        continue;
      Vec<dim> x = w.s[g];
      for (int a = 0; a < dim; ++a)
        x[a] += k[a];
      double d2 = 0;
      for (int a = 0; a < dim; ++a) {
        const double gap = std::max({lo[a] - x[a], 0.0, x[a] - hi[a]}) * w.cell.length[a];
        d2 += gap * gap;
      }
      if (d2 < width * width) {
        ghost_g.push_back(g);
        ghost_k.push_back(k);
      }
    }
  }
  std::shuffle(owned.begin(), owned.end(), rng);
  std::vector<std::size_t> perm(ghost_g.size());
  std::iota(perm.begin(), perm.end(), std::size_t{0});
  std::shuffle(perm.begin(), perm.end(), rng);
  auto particle = [&](std::size_t g, const std::array<int, dim>& k) {
    Particle<dim> q;
    q.id = w.id[g];
    q.radius = w.radius[g];
    q.mass = 1;
    q.position = w.s[g];
    for (int a = 0; a < dim; ++a)
      q.position[a] += k[a];
    return q;
  };
  const std::array<int, dim> zero{};
  for (std::size_t g : owned) {
    v.p.add_owned(particle(g, zero));
    v.grain.push_back(g);
    v.shift.push_back(zero);
  }
  for (std::size_t m : perm) {
    v.p.add_ghost(particle(ghost_g[m], ghost_k[m]));
    v.grain.push_back(ghost_g[m]);
    v.shift.push_back(ghost_k[m]);
  }
  return v;
}

/// The pairs of a list, as physical pairs; fails the test on a duplicate.
template <int dim>
std::set<PairKey<dim>> listed_pairs(const VerletList<dim>& list, const RankView<dim>& v) {
  std::set<PairKey<dim>> out;
  list.for_each_pair([&](std::size_t i, std::size_t j) {
    EXPECT_LT(i, v.p.n_owned());
    EXPECT_LT(v.p.id[i], v.p.id[j]);
    const auto key = PairKey<dim>{v.p.id[i], v.p.id[j], v.shift[j]};
    EXPECT_TRUE(out.insert(key).second) << "pair listed twice";
  });
  return out;
}

/// All physical pairs of the periodic world with |r_ab| < R_a + R_b + extra (minimum image;
/// valid when every L > 2 cutoffs).
template <int dim> std::set<PairKey<dim>> brute_force_pairs(const World<dim>& w, double extra) {
  std::set<PairKey<dim>> out;
  for (std::size_t a = 0; a < w.s.size(); ++a)
    for (std::size_t b = a + 1; b < w.s.size(); ++b) {
      Vec<dim> ds = w.s[b] - w.s[a];
      std::array<int, dim> k;
      for (int c = 0; c < dim; ++c) {
        k[c] = -static_cast<int>(std::nearbyint(ds[c]));
        ds[c] += k[c];
      }
      const double cut = w.radius[a] + w.radius[b] + extra;
      if (w.cell.length.cwiseProduct(ds).squaredNorm() >= cut * cut)
        continue;
      if (w.id[a] < w.id[b]) {
        out.insert({w.id[a], w.id[b], k});
      } else {
        for (auto& x : k)
          x = -x;
        out.insert({w.id[b], w.id[a], k});
      }
    }
  return out;
}

/// Local pairs (i owned, j local, id_i < id_j) with |L (s_j - s_i)| < R_i + R_j + extra.
template <int dim>
std::vector<std::pair<std::size_t, std::size_t>>
local_brute_force(const ParticleStore<dim>& p, const Cell<dim>& cell, double extra) {
  std::vector<std::pair<std::size_t, std::size_t>> out;
  for (std::size_t i = 0; i < p.n_owned(); ++i)
    for (std::size_t j = 0; j < p.size(); ++j) {
      if (p.id[j] <= p.id[i])
        continue;
      const double cut = p.radius[i] + p.radius[j] + extra;
      if (cell.length.cwiseProduct(p.position[j] - p.position[i]).squaredNorm() < cut * cut)
        out.emplace_back(i, j);
    }
  return out;
}

template <int dim> bool listed(const VerletList<dim>& list, std::size_t i, std::size_t j) {
  const auto nb = list.neighbors(i);
  return std::binary_search(nb.begin(), nb.end(), static_cast<std::uint32_t>(j));
}

} // namespace granpack::test
