#pragma once
// Bond-orientational order of sphere packings (3D), [AR] sec. III D, eqs. (31)-(34), tables II,
// VII and VIII; definitions, conventions and the distributed recipe in docs/analysis-order.md.
//
// A *bond* joins grains i and j closer than d_c (1.35a or 1.40a in table II). Per grain:
//   q^_lm(i) = (1/N_b(i)) sum_j Y_lm(n_ij)                                   eq. (32)
//   Q_l^loc(i) = [4 pi/(2l+1) sum_m |q^_lm(i)|^2]^(1/2)                      eq. (31)
//   qbar_lm(i) = q^_lm(i) / [sum_m |q^_lm(i)|^2]^(1/2)                        eq. (33)
//   bond ij crystalline  <=>  |sum_m qbar_6m(i) qbar_6m(j)^*| >= 0.5          eq. (34)
//   grain crystalline    <=>  at least 7 crystalline bonds
// plus the global Q_6 (average of Y_6m over all bonds of the sample), clusters of crystalline
// grains and their mass-averaged size <n_cr> = sum s^2 / sum s, and the (Q^4, Q^6) windows of
// tables VII-VIII.
//
// The API is staged so that a distributed driver exchanges only small things (MPI-free here):
//   1. local_q(neighborhood, l) per owned grain -> q^_lm(i), Q_l(i);
//   2. the owners' normalised qbar_6m (13 complex numbers per grain) go to the ranks holding
//      the grain as a ghost (QBarTable); crystalline_neighbors() then decides each bond;
//   3. BondOrderTally (global Q_6 partial sums and counts) is all-reduced (merge());
//   4. crystalline grains and their crystalline bonds are gathered on one rank for
//      crystalline_clusters() (serial union-find).
// bond_order_periodic() composes the stages serially for a whole periodic configuration.
#include <complex>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

#include "granpack/core/vec.h"

namespace granpack {

/// Coefficients indexed by m + l, m = -l..l (2l+1 entries).
using QlmVector = std::vector<std::complex<double>>;

/// The bonds of one OWNED grain, built by the caller (ghosts included as neighbours).
struct BondNeighborhood {
  GlobalId id = 0;
  std::vector<Vec<3>> bonds;          ///< r_ij (real, minimum image) to every j with |r_ij| < d_c
  std::vector<GlobalId> neighbor_ids; ///< ids of those j, same order as `bonds`
};

/// Y_lm(n) for m = -l..l at the direction of `direction` (any non-zero length), physics
/// convention with the Condon-Shortley phase (std::sph_legendre); Y_l,-m = (-1)^m Y_lm^*.
QlmVector spherical_harmonics(int l, const Vec<3>& direction);

/// Q_l = [4 pi/(2l+1) sum_m |q_m|^2]^(1/2) of eq. (31), for a vector of 2l+1 coefficients.
double rotational_invariant(std::span<const std::complex<double>> q);

/// Stage 1: local bond order of one grain for one l.
struct LocalBondOrder {
  int l = 0;
  int n_bonds = 0; ///< N_b(i)
  QlmVector q;     ///< q^_lm(i) of eq. (32); all zero when n_bonds == 0
  double Q = 0;    ///< Q_l^loc(i) of eq. (31); 0 when n_bonds == 0

  /// qbar_lm(i) of eq. (33): q scaled to unit norm; all zero when q is zero (no bond), so
  /// such a grain has no crystalline bond.
  QlmVector normalized() const;
};

/// Stage 1 on bare bond vectors, summed in the given order. Throws granpack::Error on a zero
/// or non-finite bond vector, or l < 0.
LocalBondOrder local_q(std::span<const Vec<3>> bonds, int l);

/// Stage 1 for an owned grain. Bonds are summed in ascending neighbour id, so the result does
/// not depend on the order the caller listed them (decomposition invariance). Throws
/// granpack::Error if bonds and ids differ in length or a neighbour id repeats (d_c larger
/// than half the cell: two images of one grain).
LocalBondOrder local_q(const BondNeighborhood& grain, int l);

/// Stage 2, one bond: |sum_m a_m b_m^*| of eq. (34). The sum is real for q vectors of real
/// directions; its modulus is symmetric in (a, b) up to rounding - crystalline_neighbors()
/// always passes the smaller id first so both ends of a bond decide identically.
double bond_correlation(std::span<const std::complex<double>> qbar_a,
                        std::span<const std::complex<double>> qbar_b);

/// Eq. (34): bond_correlation(qbar_i, qbar_j) >= threshold. Both of size 2l+1, l = 6 in [AR].
bool is_crystalline_bond(std::span<const std::complex<double>> qbar_i,
                         std::span<const std::complex<double>> qbar_j, double threshold = 0.5);

/// Stage 2: normalised qbar_lm of one l for the grains a rank knows (owned + ghosts), keyed by
/// global id and stored flat (values() is (2l+1) complex numbers per id, in ids() order), so
/// that the owned part can be sent as (ids, values) and the received part inserted back.
class QBarTable {
public:
  explicit QBarTable(int l = 6);
  int l() const { return l_; }
  std::size_t size() const { return ids_.size(); }
  /// Adds or replaces the entry of `id`; qbar must have 2l+1 entries.
  void insert(GlobalId id, std::span<const std::complex<double>> qbar);
  /// Entry of `id`, empty span if absent.
  std::span<const std::complex<double>> find(GlobalId id) const;
  const std::vector<GlobalId>& ids() const { return ids_; }
  const std::vector<std::complex<double>>& values() const { return values_; }

private:
  int l_;
  std::vector<GlobalId> ids_;
  std::vector<std::complex<double>> values_;
  std::unordered_map<GlobalId, std::size_t> index_;
};

/// Stage 2: ids of the neighbours of `grain` joined to it by a crystalline bond (eq. 34),
/// in the order of grain.neighbor_ids; their count is the grain's crystalline coordination.
/// Throws granpack::Error if the table lacks the grain or one of its neighbours (the halo
/// must carry qbar for every grain within d_c of an owned one).
std::vector<GlobalId> crystalline_neighbors(const BondNeighborhood& grain, const QBarTable& qbar,
                                            double threshold = 0.5);

/// Stage 3: partial sums for the global Q_l - Y_lm summed over the bonds of the grains added,
/// and their count. Every bond is met from both ends (each owner adds its grain's bonds), i.e.
/// in both directions; for even l, Y_lm(-n) = Y_lm(n), so this equals the average over
/// undirected bonds - odd l (identically zero then) is refused.
struct GlobalQlSum {
  int l = 6;
  QlmVector sum_y;          ///< sum over bonds of Y_lm(n_ij), m = -l..l (2(2l+1) doubles)
  std::int64_t n_bonds = 0; ///< number of (directed) bonds summed

  explicit GlobalQlSum(int l_ = 6);
  /// Adds the bonds of one grain: N_b(i) q^_lm(i).
  void add(const LocalBondOrder& grain);
  void merge(const GlobalQlSum& other);
  /// Global Q_l: eq. (31) applied to sum_y / n_bonds; 0 when there is no bond.
  double value() const;
};

/// Stage 3: everything table II needs, summed over grains; all-reduce or merge() then read.
struct BondOrderTally {
  std::int64_t n_grains = 0;            ///< grains added
  std::int64_t n_grains_with_bonds = 0; ///< of which with N_b >= 1 (Q_6^loc defined)
  std::int64_t n_bonds = 0;             ///< sum of N_b(i) (each bond twice)
  std::int64_t n_crystalline_bonds = 0; ///< sum of crystalline bonds per grain (each twice)
  std::int64_t n_crystalline_grains = 0;
  double sum_q6_loc = 0;             ///< sum of Q_6^loc(i) over grains with bonds
  double sum_q6_loc_crystalline = 0; ///< sum of Q_6^loc(i) over crystalline grains
  GlobalQlSum global_q6{6};

  /// Adds one grain: its l = 6 local order and number of crystalline bonds.
  void add(const LocalBondOrder& q6, int crystalline_bonds, int min_crystalline_bonds = 7);
  void merge(const BondOrderTally& other);

  /// Every member as doubles, for ONE MPI_Allreduce(MPI_SUM) of the whole tally: the 8
  /// counts/sums in declaration order (global_q6.n_bonds last), then Re, Im of
  /// global_q6.sum_y (m = -6..6). Counts stay exact below 2^53.
  static constexpr std::size_t kPackedHeader = 8;
  std::vector<double> packed() const;
  static BondOrderTally unpacked(std::span<const double> sums);

  double z() const;                                      ///< Z: mean bonds per grain
  double z_cr() const;                                   ///< Z_cr: mean crystalline bonds per grain
  double q6_global() const { return global_q6.value(); } ///< Q_6
  double q6_loc() const;                                 ///< <Q_6^loc> over grains with bonds
  double q6_loc_cr() const; ///< <Q_6^loc> over crystalline grains (0 if none)
  double x_cr() const;      ///< fraction of crystalline grains
};

/// Stage 4: connected components ("crystalline clusters") of the crystalline grains linked by
/// the given bonds. Bonds with an end not among `grains` are ignored, so a driver may send
/// every crystalline bond of its crystalline grains without knowing whether the other end is
/// crystalline; duplicates (a bond listed from both ends) are harmless. Throws granpack::Error
/// if a grain id repeats.
struct CrystallineClusters {
  std::vector<std::int64_t> sizes;     ///< cluster sizes, descending (ties: smallest member id)
  std::vector<std::size_t> cluster_of; ///< per input grain: index into sizes
  double mass_average_size = 0;        ///< <n_cr> = sum s^2 / sum s (table II); 0 if no grain
};
CrystallineClusters crystalline_clusters(
    const std::vector<GlobalId>& crystalline_grains,
    const std::vector<std::pair<GlobalId, GlobalId>>& crystalline_bonds_between_them);

/// Stage 5: local-configuration windows (Q^4 +- 0.05, Q^6 +- 0.05) of [AR] app. D.
enum class LocalOrder { disordered, fcc, hcp };
std::string_view to_string(LocalOrder kind); ///< "dis", "fcc", "hcp" (the tables' columns)

/// The experimental samples of Aste et al. ([AR] ref. 7) whose most frequent (Q^4, Q^6) define
/// the "dis" windows. Beware the names: Aste's D and B are NOT [AR]'s states D and B.
enum class AsteSample {
  any, ///< fcc and hcp windows: same for every sample and d_c
  F,   ///< dense, Phi = 0.640 (table VII; compared with [AR] states A, A', C)
  D,   ///< Phi = 0.626 (table VIII; compared with [AR] state B)
  B,   ///< loose, Phi = 0.596 (table VIII; compared with [AR] state D)
};

struct OrderWindow {
  LocalOrder kind = LocalOrder::disordered;
  double q4 = 0, q6 = 0;    ///< centre (Q^4, Q^6)
  double half_width = 0.05; ///< on both axes
  AsteSample sample = AsteSample::any;
  double d_c_over_a = 0;   ///< d_c of the "dis" centre; 0 for fcc/hcp (any d_c)
  std::string_view source; ///< where the numbers are printed in [AR]
  /// Closed window: |Q4 - q4| <= half_width and |Q6 - q6| <= half_width.
  bool contains(double Q4, double Q6) const;
};

/// All windows of tables VII-VIII: fcc, hcp, then the 12 "dis" windows (3 samples x d_c =
/// 1.1, 1.2, 1.3, 1.4 a).
std::span<const OrderWindow> order_windows();

/// The three windows to use for one comparison: {dis of `sample` at d_c, fcc, hcp}. Throws
/// granpack::InputError unless d_c_over_a is one of 1.1, 1.2, 1.3, 1.4 (to 1e-9) and sample
/// is F, D or B.
std::vector<OrderWindow> windows_for(AsteSample sample, double d_c_over_a);

/// The Aste sample [AR] compares a state with: "A", "A'", "C" -> F; "B" -> D; "D" -> B.
/// Throws granpack::InputError for any other state name.
AsteSample aste_sample_compared_with(std::string_view ar_state);

/// Indices (into `windows`) of the windows containing (Q4, Q6); windows may overlap
/// (e.g. hcp and the dense-sample dis window at d_c = 1.2a), so several may be returned.
std::vector<std::size_t> windows_containing(double Q4, double Q6,
                                            std::span<const OrderWindow> windows);

/// Serial, all-in-one: every grain's bonds in a periodic orthorhombic cell (real positions,
/// any image; ids = indices), then stages 1-4. For tests and small samples.
struct BondOrderParams {
  double d_c = 1.4;              ///< bond distance (real units), < half the smallest cell length
  double threshold = 0.5;        ///< eq. (34)
  int min_crystalline_bonds = 7; ///< "at least 7 of its bonds"
};
struct GrainBondOrder {
  GlobalId id = 0;
  int n_bonds = 0;
  double q4 = 0, q6 = 0; ///< Q_4^loc(i), Q_6^loc(i)
  int n_crystalline_bonds = 0;
  bool crystalline = false;
};
struct BondOrderResult {
  std::vector<GrainBondOrder> grains; ///< in input order
  BondOrderTally tally;               ///< Z, Z_cr, Q_6, Q_6^loc, Q_6^loc,cr, x_cr
  CrystallineClusters clusters;       ///< <n_cr> = clusters.mass_average_size
};

/// Bonds of every grain (|r_ij| < d_c, minimum image) in a periodic cell of the given lengths;
/// neighbours listed in ascending id. Throws granpack::Error unless 0 < d_c < min(L)/2.
std::vector<BondNeighborhood> periodic_neighborhoods(const std::vector<Vec<3>>& real_positions,
                                                     const Vec<3>& lengths, double d_c);

BondOrderResult bond_order_periodic(const std::vector<Vec<3>>& real_positions,
                                    const Vec<3>& lengths, const BondOrderParams& params);

} // namespace granpack
