#pragma once
// Force statistics of cohesive interaction networks ([GRC] sec. IV A-B), MPI-free kernels.
//
// An *interaction* is a contact or a distant cohesive pair (gap below D0). Its total normal
// force is N = N^e + N^a (N^a = -F0 in contact, -F0 (1 - g/D0) across a gap g; [GRC] eq. 4-5),
// its tangential force T (zero for distant pairs), |F| = |N n + T|.
//  - the distribution of N / F_s (F_s = F0 with cohesion, <N^e> without: fig. 9);
//  - the angle theta between n and F, theta = atan2(|T|, N) in degrees: 0 for a repulsive
//    force along n, 180 for a tensile one (fig. 15); the ratio |T/N| = sqrt(3) of eq. (20) is
//    theta = 60 and 120;
//  - the Rumpf relation: the mean N against pi P <d^D> / (<d> z Phi) (eq. 17; eq. 18 for
//    diameters uniform in [a/2, a] in 2D), z counting all interactions;
//  - the percolation threshold F_perc: the largest F such that the interactions with |F| >= F
//    contain a cluster that wraps around the periodic cell (sec. IV B 1), found by adding
//    interactions in decreasing |F| to a union-find that tracks each grain's periodic image
//    offset from its root (a cycle with a non-zero net offset wraps).
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "granpack/core/vec.h"

namespace granpack {

/// One interaction as the percolation search needs it: grains by dense index 0..n-1, the
/// periodic image offset `shift` of the second grain (x_j + shift . L - x_i is the branch
/// vector) and the force magnitude.
template <int dim> struct PercolationEdge {
  std::int64_t i = 0, j = 0;
  std::array<int, dim> shift{};
  double force = 0;
};

struct PercolationResult {
  double threshold_any = 0;      ///< F_perc: first wrap in some direction (0: never wraps)
  double threshold_all = 0;      ///< first time the wrapping vectors span every direction
  std::int64_t edges_at_any = 0; ///< interactions with |F| >= F_perc
};

/// Edges are sorted here by decreasing force (ties by (i, j)), so the result does not depend
/// on their order.
template <int dim>
PercolationResult percolation_threshold(std::vector<PercolationEdge<dim>> edges, std::int64_t n);

/// Histogram on uniform bins [lo, hi) plus the counts below lo and at or above hi.
struct Histogram {
  double lo = 0, hi = 1;
  std::vector<double> counts;
  double below = 0, above = 0;
  Histogram(double lo_, double hi_, std::size_t bins) : lo(lo_), hi(hi_), counts(bins, 0.0) {}
  void add(double x);
  double total() const;
  /// Probability density per bin (counts / (total * width)).
  std::vector<double> pdf() const;
  std::vector<double> edges() const;
};

/// theta = atan2(|T|, N) in degrees, in [0, 180].
inline double force_angle_degrees(double normal, double tangential_magnitude) {
  return std::atan2(tangential_magnitude, normal) * 180.0 / 3.14159265358979323846;
}

/// Rumpf's eq. (17): the mean normal force predicted from P, z, Phi and the diameter moments.
double rumpf_mean_force(double pressure, double z, double phi, double mean_d,
                        double mean_d_pow_dim);

} // namespace granpack
