#include "granpack/core/cut_planes.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "granpack/core/error.h"

namespace granpack {

std::vector<double> uniform_cuts(int slabs) {
  GRANPACK_CHECK(slabs >= 1, "uniform_cuts: " << slabs << " slabs");
  std::vector<double> c(static_cast<std::size_t>(slabs) + 1);
  // double(k) / slabs: the same expression as the static grid's sub-box bounds always used.
  for (int k = 0; k <= slabs; ++k)
    c[k] = double(k) / slabs;
  return c;
}

std::vector<double> quantile_cuts(std::span<const std::int64_t> histogram, int slabs,
                                  double min_width) {
  GRANPACK_CHECK(slabs >= 1 && !histogram.empty(),
                 "quantile_cuts: " << slabs << " slabs, " << histogram.size() << " bins");
  GRANPACK_CHECK(slabs * min_width <= 1.0,
                 "quantile_cuts: " << slabs << " slabs of at least " << min_width << " do not fit");
  std::int64_t total = 0;
  for (const std::int64_t h : histogram)
    total += h;
  if (total == 0)
    return uniform_cuts(slabs);
  const double bins = static_cast<double>(histogram.size());
  std::vector<double> c(static_cast<std::size_t>(slabs) + 1);
  c.front() = 0.0;
  c.back() = 1.0;
  // Cut k where the cumulative count reaches k total / slabs (integer comparison: exact).
  std::size_t b = 0;
  std::int64_t below = 0; // count in bins [0, b)
  for (int k = 1; k < slabs; ++k) {
    // target = k * total / slabs, compared as k * total against slabs * cumulative.
    const std::int64_t scaled_target = k * total;
    while (b < histogram.size() && slabs * (below + histogram[b]) < scaled_target)
      below += histogram[b++];
    if (b == histogram.size()) {
      c[k] = 1.0;
      continue;
    }
    // Inside bin b, proportionally to the missing count.
    const double missing = static_cast<double>(scaled_target - slabs * below) / slabs;
    const double inside = histogram[b] > 0 ? missing / static_cast<double>(histogram[b]) : 0.0;
    c[k] = (static_cast<double>(b) + std::clamp(inside, 0.0, 1.0)) / bins;
  }
  // Widen the narrow slabs: push cuts up from the left, then down from the right. After both
  // passes c_k >= k w and c_slabs - c_k >= (slabs - k) w, so every slab is >= w.
  for (int k = 1; k < slabs; ++k)
    c[k] = std::max(c[k], c[k - 1] + min_width);
  for (int k = slabs - 1; k >= 1; --k)
    c[k] = std::min(c[k], c[k + 1] - min_width);
  return c;
}

namespace {
/// Greedy slabs of at least `min_bins` bins, each as long as no cell exceeds `bound`: the slab
/// start bins, or nothing when more than `slabs` slabs are needed or the last is too narrow.
std::vector<std::size_t> greedy_slabs(std::span<const std::int64_t> h, std::size_t columns,
                                      std::size_t bins, int slabs, std::size_t min_bins,
                                      std::int64_t bound) {
  std::vector<std::size_t> starts;
  std::vector<std::int64_t> acc(columns, 0);
  std::size_t b = 0;
  while (b < bins) {
    if (starts.size() == static_cast<std::size_t>(slabs))
      return {};
    starts.push_back(b);
    std::fill(acc.begin(), acc.end(), 0);
    const std::size_t forced = std::min(bins, b + min_bins);
    for (; b < forced; ++b)
      for (std::size_t c = 0; c < columns; ++c)
        if ((acc[c] += h[b * columns + c]) > bound)
          return {};
    for (; b < bins; ++b) {
      bool fits = true;
      for (std::size_t c = 0; c < columns && fits; ++c)
        fits = acc[c] + h[b * columns + c] <= bound;
      if (!fits)
        break;
      for (std::size_t c = 0; c < columns; ++c)
        acc[c] += h[b * columns + c];
    }
  }
  if (bins - starts.back() < min_bins)
    return {};
  return starts;
}
} // namespace

std::vector<double> minmax_cuts(std::span<const std::int64_t> histogram, std::size_t columns,
                                int slabs, double min_width) {
  GRANPACK_CHECK(slabs >= 1 && columns >= 1 && !histogram.empty() &&
                     histogram.size() % columns == 0,
                 "minmax_cuts: " << slabs << " slabs, " << histogram.size() << " counts in "
                                 << columns << " columns");
  GRANPACK_CHECK(slabs * min_width <= 1.0,
                 "minmax_cuts: " << slabs << " slabs of at least " << min_width << " do not fit");
  const std::size_t bins = histogram.size() / columns;
  // Slabs of whole bins at least min_width wide (rounded up), when the bins allow it.
  std::size_t min_bins = static_cast<std::size_t>(std::ceil(min_width * static_cast<double>(bins)));
  min_bins = std::max<std::size_t>(1, std::min(min_bins, bins / static_cast<std::size_t>(slabs)));
  if (bins < static_cast<std::size_t>(slabs))
    return uniform_cuts(slabs);
  std::int64_t lo = 0, hi = 0; // infeasible / feasible bounds on the largest cell
  for (const std::int64_t v : histogram)
    hi += v;
  std::vector<std::size_t> best = greedy_slabs(histogram, columns, bins, slabs, min_bins, hi);
  if (best.empty()) // only when the widths allow just the uniform bins
    return uniform_cuts(slabs);
  while (hi - lo > 1) {
    const std::int64_t mid = lo + (hi - lo) / 2;
    auto starts = greedy_slabs(histogram, columns, bins, slabs, min_bins, mid);
    if (starts.empty()) {
      lo = mid;
    } else {
      hi = mid;
      best = std::move(starts);
    }
  }
  // Fewer slabs than asked: split the widest (no cell grows) until there are enough.
  while (best.size() < static_cast<std::size_t>(slabs)) {
    std::size_t widest = 0, width = 0;
    for (std::size_t k = 0; k < best.size(); ++k) {
      const std::size_t w = (k + 1 < best.size() ? best[k + 1] : bins) - best[k];
      if (w > width)
        widest = k, width = w;
    }
    if (width < 2 * min_bins)
      return uniform_cuts(slabs); // cannot happen while slabs * min_bins <= bins
    best.insert(best.begin() + static_cast<std::ptrdiff_t>(widest) + 1, best[widest] + width / 2);
  }
  std::vector<double> c(static_cast<std::size_t>(slabs) + 1);
  for (int k = 0; k < slabs; ++k)
    c[k] = static_cast<double>(best[k]) / static_cast<double>(bins);
  c[0] = 0.0;
  c[slabs] = 1.0;
  return c;
}

double narrowest_slab(std::span<const double> cuts) {
  double w = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k + 1 < cuts.size(); ++k)
    w = std::min(w, cuts[k + 1] - cuts[k]);
  return w;
}

} // namespace granpack
