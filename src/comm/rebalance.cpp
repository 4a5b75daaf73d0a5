#include "granpack/comm/rebalance.h"

#include <algorithm>
#include <cstdint>

#include "granpack/comm/communicator.h"
#include "granpack/comm/reduce.h"
#include "granpack/core/cut_planes.h"
#include "granpack/core/error.h"

namespace granpack {

namespace {
/// Bins per slab of the histogram the cuts are read from: a cut lands within 1/128 of a mean
/// slab of its quantile (linear inside the bin), far finer than the count fluctuations.
constexpr int kBinsPerSlab = 128;
} // namespace

double load_imbalance(MPI_Comm comm, std::int64_t local_load) {
  std::array<std::int64_t, 1> largest{local_load};
  global_max_in_place(comm, largest);
  const std::int64_t total = global_sum(comm, local_load);
  if (total == 0)
    return 1.0;
  return static_cast<double>(largest[0]) * size_of(comm) / static_cast<double>(total);
}

namespace {
/// Slab of `cuts` holding x (the slab above a plane that x lies on).
int slab_of(const std::vector<double>& cuts, double x) {
  return static_cast<int>(std::upper_bound(cuts.begin() + 1, cuts.end() - 1, x) -
                          (cuts.begin() + 1));
}

std::size_t bin_of(double s, std::size_t bins) {
  return std::min(bins - 1, static_cast<std::size_t>(std::max(0.0, s * static_cast<double>(bins))));
}
} // namespace

template <int dim>
std::array<std::vector<double>, dim>
balanced_cuts(const Decomposition<dim>& d, const ParticleStore<dim>& p,
              std::span<const std::int64_t> weights, const Vec<dim>& min_width) {
  GRANPACK_CHECK(weights.empty() || weights.size() == p.n_owned(),
                 "balanced_cuts: " << weights.size() << " weights for " << p.n_owned()
                                   << " grains");
  const auto weight = [&](std::size_t i) { return weights.empty() ? 1 : weights[i]; };
  const auto& dims = d.dims();
  // Start: every axis at the quantiles of its grains, all axes' histograms in one all-reduce.
  // Integer counts: the sums are exact and independent of the order of the ranks.
  std::array<std::size_t, dim> first{}, bins{};
  std::size_t total = 0;
  for (int a = 0; a < dim; ++a) {
    bins[a] = static_cast<std::size_t>(kBinsPerSlab) * static_cast<std::size_t>(dims[a]);
    first[a] = total;
    total += bins[a];
  }
  std::vector<std::int64_t> h(total, 0);
  for (std::size_t i = 0; i < p.n_owned(); ++i)
    for (int a = 0; a < dim; ++a)
      h[first[a] + bin_of(p.position[i][a], bins[a])] += weight(i);
  global_sum_in_place(d.comm(), h);
  std::array<std::vector<double>, dim> cuts;
  for (int a = 0; a < dim; ++a) {
    const std::span<const std::int64_t> axis(h.data() + first[a], bins[a]);
    cuts[a] = dims[a] == 1 ? uniform_cuts(1) : quantile_cuts(axis, dims[a], min_width[a]);
  }
  // Quantiles balance each axis' slabs, not the cells where slabs cross (a 2D aggregate on 4 x 4
  // ranks: 1.25 grains on the fullest rank over the mean either way). Then, axis by axis, the
  // cuts that minimise the fullest cell given the other axes' cuts (minmax_cuts), a few rounds.
  constexpr int kRounds = 3;
  for (int round = 0; round < kRounds; ++round) {
    for (int a = 0; a < dim; ++a) {
      if (dims[a] == 1)
        continue;
      std::size_t columns = 1;
      for (int b = 0; b < dim; ++b)
        if (b != a)
          columns *= static_cast<std::size_t>(dims[b]);
      std::vector<std::int64_t> hc(bins[a] * columns, 0);
      for (std::size_t i = 0; i < p.n_owned(); ++i) {
        std::size_t column = 0;
        for (int b = 0; b < dim; ++b)
          if (b != a)
            column = column * static_cast<std::size_t>(dims[b]) +
                     static_cast<std::size_t>(slab_of(cuts[b], p.position[i][b]));
        hc[bin_of(p.position[i][a], bins[a]) * columns + column] += weight(i);
      }
      global_sum_in_place(d.comm(), hc);
      cuts[a] = minmax_cuts(hc, columns, dims[a], min_width[a]);
    }
  }
  return cuts;
}

template <int dim>
bool planes_too_narrow(const Decomposition<dim>& d, const Vec<dim>& ghost_width) {
  bool narrow = false;
  for (int a = 0; a < dim; ++a)
    narrow = narrow || d.narrowest(a) < ghost_width[a];
  return narrow && !d.uniform();
}

template <int dim>
bool rebalance(Decomposition<dim>& d, const ParticleStore<dim>& p,
               std::span<const std::int64_t> weights, const Vec<dim>& ghost_width, double margin) {
  Vec<dim> min_width;
  for (int a = 0; a < dim; ++a)
    min_width[a] = std::min(margin * ghost_width[a], 1.0 / d.dims()[a]);
  auto cuts = balanced_cuts(d, p, weights, min_width);
  bool moved = false;
  for (int a = 0; a < dim; ++a)
    moved = moved || cuts[a] != d.cuts(a);
  if (moved)
    d.set_cuts(cuts);
  return moved;
}

template std::array<std::vector<double>, 2> balanced_cuts<2>(const Decomposition<2>&,
                                                             const ParticleStore<2>&,
                                                             std::span<const std::int64_t>,
                                                             const Vec<2>&);
template std::array<std::vector<double>, 3> balanced_cuts<3>(const Decomposition<3>&,
                                                             const ParticleStore<3>&,
                                                             std::span<const std::int64_t>,
                                                             const Vec<3>&);
template bool planes_too_narrow<2>(const Decomposition<2>&, const Vec<2>&);
template bool planes_too_narrow<3>(const Decomposition<3>&, const Vec<3>&);
template bool rebalance<2>(Decomposition<2>&, const ParticleStore<2>&,
                           std::span<const std::int64_t>, const Vec<2>&, double);
template bool rebalance<3>(Decomposition<3>&, const ParticleStore<3>&,
                           std::span<const std::int64_t>, const Vec<3>&, double);

} // namespace granpack
