#pragma once
// [GRC] table VI: the interactions (contacts and distant cohesive pairs) split by the sign of
// their total normal force N = N^e + N^a beyond the vanishing tolerance t: repulsive N > t,
// attractive N < -t, vanishing |N| <= t (the populations of z+, z-, z0), with the mean and
// the quadratic mean of |N| and of |T| in each. The sums add over ranks (the app reduces
// them); MPI-free.
#include <array>

namespace granpack {

enum class ForceSign { repulsive = 0, attractive = 1, vanishing = 2 };

inline ForceSign force_sign(double normal, double tolerance) {
  return normal > tolerance ? ForceSign::repulsive
                            : (normal < -tolerance ? ForceSign::attractive : ForceSign::vanishing);
}

struct ForceSignSums {
  static constexpr int fields = 5; ///< count, sum |N|, sum N^2, sum |T|, sum |T|^2
  std::array<double, 3 * fields> sums{};
  void add(double normal, double tangential_magnitude, double tolerance);
};

/// Means of one class over its interactions (NaN when the class is empty).
struct ForceSignMeans {
  double count = 0;
  double mean_normal = 0, rms_normal = 0;         ///< <|N|>, <N^2>^(1/2)
  double mean_tangential = 0, rms_tangential = 0; ///< <|T|>, <|T|^2>^(1/2)
};
ForceSignMeans force_sign_means(const ForceSignSums& s, ForceSign c);

} // namespace granpack
