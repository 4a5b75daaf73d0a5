#pragma once
// Contact-force statistics of [AR] (docs/analysis-statistics.md): the distribution P(f) of
// f = N/<N> (fig. 4, 15), the moments Z(alpha) = <N^alpha>/<N>^alpha (eq. 27), the strong/weak
// split of table VI (X1, M1, M2 and the same for contacts of 2- and 3-coordinated grains), the
// check of eq. (22), the density increment of eq. (26)/(28) and Phi_0, and the degree of
// hyperstaticity per degree of freedom of eq. (37).
//
// Distributed use (MPI-free here; the driver reduces). Each rank passes ITS contacts, every
// contact being passed on exactly one rank. Two passes, each a flat array of sums that is
// all-reduced elementwise (MPI_SUM) in place:
//   pass 1  ForceMomentSums  (count, sum N, sum N^alpha, sum N h)  -> <N> = mean_normal_force()
//   pass 2  ForceSplitSums   (histogram of N/<N>, strong/weak sums) built with the global <N>
// then finish_force_statistics<dim>(pass1, pass2, scales) on every rank. The layout of each
// array is fixed by the constructor arguments, which must be the same on every rank.
#include <cstdint>
#include <span>
#include <vector>

namespace granpack {

/// One force-carrying contact as the force statistics see it.
struct ContactForceSample {
  double normal_force = 0;     ///< N, the elastic normal force (> 0 on a carrying contact)
  double tangential_force = 0; ///< |T|
  double deflection = 0;       ///< h, the normal overlap (length), for eq. (26)
  int coordination_i = 0;      ///< backbone coordination of one grain (c_i)
  int coordination_j = 0;      ///< backbone coordination of the other (c_j)
};

/// Pass 1: sums that need no global quantity. Flat layout of sums():
///   [0] contact count N_c, [1] sum N, [2] sum N h, [3] sum N^{5/3},
///   [4 + k] sum N^{alpha_k} for the alphas given to the constructor.
class ForceMomentSums {
public:
  /// `alphas`: the orders of the moments Z(alpha) to compute (5/3 is always kept for eq. 28).
  explicit ForceMomentSums(std::vector<double> alphas = {5.0 / 3.0, 2.0});

  void add(const ContactForceSample& c);
  void add(std::span<const ContactForceSample> contacts);
  /// Elementwise sum of another partial with the same alphas (two "ranks" in one process).
  void merge(const ForceMomentSums& other);

  /// The flat array of partial sums: all-reduce it in place (MPI_SUM) across ranks.
  std::vector<double>& sums() { return sums_; }
  const std::vector<double>& sums() const { return sums_; }
  const std::vector<double>& alphas() const { return alphas_; }

  double contacts() const { return sums_[0]; }
  /// <N> of the contacts summed so far (global after the reduction); NaN if there are none.
  double mean_normal_force() const;

private:
  std::vector<double> alphas_;
  std::vector<double> sums_;
};

/// Bins of P(f): `bins` equal bins on [0, f_max), plus an overflow (f >= f_max) and an
/// underflow (f < 0, only with cohesion) count.
struct ForceBins {
  double f_max = 5.0;
  int bins = 50;
};

/// One population of contacts for the strong/weak split ([AR] table VI).
enum class ForcePopulation : int {
  all = 0,       ///< every contact
  divalent = 1,  ///< contacts with at least one grain of backbone coordination 2
  trivalent = 2, ///< contacts with at least one grain of backbone coordination 3
};

/// Pass 2: sums that need the global <N>. Flat layout of sums():
///   [0, bins)            contacts with f = N/<N> in bin k = floor(f / (f_max/bins))
///   [bins]               overflow, f >= f_max
///   [bins + 1]           underflow, f < 0
///   [bins + 2 + 7 p + q] population p (ForcePopulation), quantity q:
///       q = 0 count, 1 count with N > <N> (strong), 2 sum N,
///           3 sum |T|/N over strong, 4 count of those,
///           5 sum |T|/N over weak (0 < N <= <N>), 6 count of those.
/// A contact with N <= 0 enters the counts but no |T|/N sum.
class ForceSplitSums {
public:
  ForceSplitSums(double mean_normal_force, ForceBins bins = {});

  void add(const ContactForceSample& c);
  void add(std::span<const ContactForceSample> contacts);
  void merge(const ForceSplitSums& other);

  std::vector<double>& sums() { return sums_; }
  const std::vector<double>& sums() const { return sums_; }
  double mean_normal_force() const { return mean_; }
  const ForceBins& bins() const { return bins_; }
  /// Value q (see the layout) of population p.
  double population(ForcePopulation p, int q) const;

  static constexpr int kPerPopulation = 7;
  static constexpr int kPopulations = 3;

private:
  double mean_;
  ForceBins bins_;
  std::vector<double> sums_;
};

/// Global quantities the driver knows: what turns sums into [AR]'s dimensionless numbers.
struct PackingScales {
  double pressure = 0;       ///< P = tr(sigma)/dim (Pa in 3D, N/m in 2D)
  double diameter = 0;       ///< a (the mean diameter of a polydisperse sample)
  double solid_fraction = 0; ///< Phi
  double n_grains = 0;       ///< n, ALL grains (rattlers included): z = 2 N_c / n
  double volume = 0;         ///< Omega, cell volume (area in 2D)
  double e_tilde = 0;        ///< Ẽ of the Hertz law N = Ẽ sqrt(a) h^{3/2}/3; 0: not Hertz
};

/// X1, M1, M2 and the mean normal force of one population ([AR] table VI). NaN when the
/// population (or the strong or weak part, for M1 and M2) is empty.
struct StrongWeakSplit {
  double contacts = 0;            ///< number of contacts in the population
  double strong_fraction = 0;     ///< X1: fraction with N > <N>
  double strong_mobilization = 0; ///< M1: mean |T|/N over N > <N>
  double weak_mobilization = 0;   ///< M2: mean |T|/N over N <= <N>
  double mean_normal_force = 0;   ///< mean N of the population / (P a^{dim-1}): N^(2), N^(3)
};

struct ForceStatistics {
  double contacts = 0;          ///< N_c
  double mean_normal_force = 0; ///< <N>
  double coordination = 0;      ///< z = 2 N_c / n
  std::vector<double> alphas;   ///< as given to ForceMomentSums
  std::vector<double> moments;  ///< Z(alpha_k), eq. (27)
  double z_5_3 = 0;             ///< Z(5/3)

  std::vector<double> f_edges; ///< bins + 1 edges of f = N/<N>
  std::vector<double> pdf;     ///< P(f) in each bin: count / (N_c * bin width)
  double fraction_above = 0;   ///< fraction of contacts with f >= f_max
  double fraction_below = 0;   ///< fraction with f < 0

  StrongWeakSplit all, divalent, trivalent;

  /// eq. (22): z Phi <N> / (pi a^2) in 3D, z Phi <N> / (pi a) in 2D, and its ratio to P.
  double pressure_eq22 = 0;
  double eq22_ratio = 0;
  /// kappa = (Ẽ/P)^{2/3} in 3D (eq. 21), (Ẽ a / P)^{2/3} in 2D; NaN without Ẽ.
  double kappa = 0;
  /// Phi - Phi_0 by eq. (26) from the measured sum N h, and by eq. (28) (Hertz, from Z(5/3),
  /// z, Phi, kappa; NaN without Ẽ); Phi_0 = Phi - DeltaPhi for each.
  double delta_phi_eq26 = 0, phi0_eq26 = 0;
  double delta_phi_eq28 = 0, phi0_eq28 = 0;
};

/// Turns the globally summed passes into the statistics. Same result on every rank.
template <int dim>
ForceStatistics finish_force_statistics(const ForceMomentSums& pass1, const ForceSplitSums& pass2,
                                        const PackingScales& scales);

/// eq. (28) and its 2D analogue: Phi - Phi_0 = c_d Phi^{1/3} Z(5/3) (pi/z)^{2/3} / kappa with
/// c_3 = 3^{5/3}, c_2 = 2 * 3^{2/3} (kappa as in ForceStatistics::kappa).
template <int dim> double delta_phi_eq28(double phi, double z, double z_5_3, double kappa);

/// Degree of force indeterminacy of the backbone, eq. (19)-(20) and (37).
struct Hyperstaticity {
  double degree = 0;           ///< H
  double dof = 0;              ///< N_f^*: n* d(d+1)/2 with friction, n* d without
  double per_dof = 0;          ///< H / N_f^*
  double z_star = 0;           ///< z* = 2 N_c^* / n*
  double z0_star = 0;          ///< z* at which H = 0 (z0* of eq. 37)
  double z_star_corrected = 0; ///< z** = z* + (d+1) - z0* (friction), z* + 2d - z0* (none)
};

/// H and H/N_f^* from the backbone counts: N_c^* force-carrying contacts between n*
/// non-rattler grains, of which n2 have exactly two such contacts. With friction each
/// contact carries d force components and each grain has d(d+1)/2 degrees of freedom; in 3D
/// each divalent grain adds one mechanism (rolling about the line through its two contact
/// points, [AR] fig. 14), in 2D none: H = d N_c^* + k_2 - n* d(d+1)/2, k_2 = n2 (3D), 0 (2D).
/// Without friction (normal forces only, rotations dropped): H = N_c^* - d n*, n2 ignored.
/// The d cell degrees of freedom cancel the d trivial translations (k_0 = d).
template <int dim>
Hyperstaticity hyperstaticity(std::int64_t backbone_contacts, std::int64_t backbone_grains,
                              std::int64_t divalent_grains, bool frictional);

} // namespace granpack
