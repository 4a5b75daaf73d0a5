#include "granpack/analysis/force_sign_classes.h"

#include <cmath>
#include <limits>

namespace granpack {

void ForceSignSums::add(double normal, double tangential_magnitude, double tolerance) {
  double* s = &sums[std::size_t(force_sign(normal, tolerance)) * fields];
  s[0] += 1;
  s[1] += std::abs(normal);
  s[2] += normal * normal;
  s[3] += tangential_magnitude;
  s[4] += tangential_magnitude * tangential_magnitude;
}

ForceSignMeans force_sign_means(const ForceSignSums& sums, ForceSign c) {
  const double* s = &sums.sums[std::size_t(c) * ForceSignSums::fields];
  const double n = s[0];
  if (n == 0) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    return {0, nan, nan, nan, nan};
  }
  return {n, s[1] / n, std::sqrt(s[2] / n), s[3] / n, std::sqrt(s[4] / n)};
}

} // namespace granpack
