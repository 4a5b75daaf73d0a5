// Random sequential addition in a periodic cube; see the header for why.
// A periodic grid of cells of side >= the largest diameter holds the placed grains as linked
// lists (head per cell, next per grain), so a trial looks at the 3^dim cells around it.
// (neighbor/cell_grid bins a fixed set once and is not periodic; this grid grows by one
// grain at a time.)
#include "granpack/neighbor/sequential_placement.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>

#include "granpack/core/error.h"
#include "granpack/core/particles.h"

namespace granpack {

template <int dim>
std::vector<Vec<dim>> place_sequentially(const std::vector<double>& diameter, double side,
                                         std::mt19937_64& rng,
                                         std::int64_t max_attempts_per_grain) {
  const std::size_t n = diameter.size();
  std::vector<Vec<dim>> s(n, Vec<dim>::Zero());
  if (n == 0)
    return s;
  GRANPACK_CHECK(side > 0 && std::isfinite(side), "sequential placement: cell side " << side);
  const double d_max = *std::max_element(diameter.begin(), diameter.end());
  GRANPACK_CHECK(d_max > 0 && d_max < side,
                 "sequential placement: largest diameter " << d_max << " vs cell side " << side);
  // Cells per axis: side/cell >= d_max, so two overlapping grains are in neighbouring cells;
  // with fewer than 3 cells every cell neighbours every other one (visited once each).
  const int per_axis = std::max(1, static_cast<int>(std::floor(side / d_max)));
  std::size_t n_cells = 1;
  for (int a = 0; a < dim; ++a)
    n_cells *= static_cast<std::size_t>(per_axis);
  std::vector<std::int64_t> head(n_cells, -1), next(n, -1);
  const bool scan_all = per_axis < 3; // below 3 cells per axis every cell is a neighbour
  const int span = scan_all ? per_axis : 3;

  auto cell_of = [&](const Vec<dim>& x) {
    std::array<int, dim> c{};
    for (int a = 0; a < dim; ++a)
      c[a] = std::min(per_axis - 1, static_cast<int>(x[a] * per_axis));
    return c;
  };
  auto flat = [&](const std::array<int, dim>& c) {
    std::size_t k = 0;
    for (int a = dim - 1; a >= 0; --a)
      k = k * per_axis + static_cast<std::size_t>(c[a]);
    return k;
  };
  auto fits = [&](std::size_t i, const Vec<dim>& x) {
    const auto c0 = cell_of(x);
    const int n_stencil = dim == 3 ? span * span * span : span * span;
    for (int k = 0; k < n_stencil; ++k) {
      // k -> one cell of the stencil: c0 + (-1..1) per axis, or every cell below 3 per axis.
      int rest = k;
      std::array<int, dim> c{};
      for (int a = 0; a < dim; ++a) {
        const int digit = rest % span;
        rest /= span;
        c[a] = scan_all ? digit : (c0[a] + digit - 1 + per_axis) % per_axis;
      }
      for (std::int64_t j = head[flat(c)]; j >= 0; j = next[static_cast<std::size_t>(j)]) {
        Vec<dim> r = x - s[static_cast<std::size_t>(j)];
        for (int a = 0; a < dim; ++a)
          r[a] -= std::round(r[a]); // nearest image
        const double contact = 0.5 * (diameter[i] + diameter[static_cast<std::size_t>(j)]) / side;
        if (r.squaredNorm() < contact * contact)
          return false;
      }
    }
    return true;
  };

  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return diameter[a] > diameter[b]; });
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t i = order[k];
    Vec<dim> x;
    std::int64_t attempt = 0;
    do {
      if (attempt++ == max_attempts_per_grain) {
        double placed = 0; // the grains before this one in `order`
        for (std::size_t j = 0; j < k; ++j)
          placed += HomogeneousGrain<dim>::volume(diameter[order[j]]);
        std::ostringstream msg;
        msg << "sequential placement: grain " << i << " (diameter " << diameter[i]
            << ") found no room after " << max_attempts_per_grain
            << " random tries, with a solid fraction of " << placed / std::pow(side, dim)
            << " already placed";
        throw Error(msg.str());
      }
      for (int a = 0; a < dim; ++a)
        x[a] = u(rng);
    } while (!fits(i, x));
    s[i] = x;
    const std::size_t c = flat(cell_of(x));
    next[i] = head[c];
    head[c] = static_cast<std::int64_t>(i);
  }
  return s;
}

template std::vector<Vec<2>> place_sequentially<2>(const std::vector<double>&, double,
                                                   std::mt19937_64&, std::int64_t);
template std::vector<Vec<3>> place_sequentially<3>(const std::vector<double>&, double,
                                                   std::mt19937_64&, std::int64_t);

} // namespace granpack
