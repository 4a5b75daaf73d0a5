#include "granpack/analysis/coordination.h"

#include <cmath>

namespace granpack {

void count_backbone_contacts(const std::vector<CarryingContact>& contacts,
                             const std::vector<std::uint8_t>& rattler,
                             std::vector<double>& counts) {
  std::fill(counts.begin(), counts.end(), 0.0);
  for (const auto& c : contacts) {
    if (rattler[c.i] || rattler[c.j])
      continue;
    counts[c.i] += 1.0;
    counts[c.j] += 1.0;
  }
}

std::size_t flag_rattlers(std::size_t n_owned, const std::vector<double>& counts, int min_contacts,
                          std::vector<std::uint8_t>& rattler) {
  std::size_t fresh = 0;
  for (std::size_t i = 0; i < n_owned; ++i) {
    if (rattler[i] || counts[i] >= min_contacts)
      continue;
    rattler[i] = 1;
    ++fresh;
  }
  return fresh;
}

std::vector<std::int64_t> coordination_histogram(std::size_t n_owned,
                                                 const std::vector<double>& counts,
                                                 const std::vector<std::uint8_t>& rattler) {
  std::vector<std::int64_t> h;
  for (std::size_t i = 0; i < n_owned; ++i) {
    if (rattler[i])
      continue;
    auto c = static_cast<std::size_t>(std::lround(counts[i]));
    if (c >= h.size())
      h.resize(c + 1, 0);
    ++h[c];
  }
  return h;
}

double sum_force_power(const std::vector<CarryingContact>& contacts, double alpha) {
  double s = 0;
  for (const auto& c : contacts)
    s += std::pow(c.normal_force, alpha);
  return s;
}

} // namespace granpack
