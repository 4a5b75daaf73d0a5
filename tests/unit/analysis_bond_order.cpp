// Bond-orientational order ([AR] sec. III D, eqs. 31-34, tables II, VII, VIII); 3D only, as
// the definitions (Y_lm on the sphere) are. docs/analysis-order.md.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "granpack/analysis/bond_order.h"
#include "granpack/core/error.h"

using namespace granpack;

namespace {

constexpr double kPi = std::numbers::pi;

/// Perfect FCC, nearest-neighbour distance a = 1: k^3 conventional cubes of side sqrt(2).
std::vector<Vec<3>> fcc(int k, Vec<3>& lengths) {
  const double side = std::sqrt(2.0);
  const double basis[4][3] = {{0, 0, 0}, {0, 0.5, 0.5}, {0.5, 0, 0.5}, {0.5, 0.5, 0}};
  std::vector<Vec<3>> p;
  for (int x = 0; x < k; ++x)
    for (int y = 0; y < k; ++y)
      for (int z = 0; z < k; ++z)
        for (const auto& b : basis)
          p.push_back(side * Vec<3>(x + b[0], y + b[1], z + b[2]));
  lengths = Vec<3>::Constant(k * side);
  return p;
}

/// Perfect HCP, a = 1, ideal c = sqrt(8/3): nx x ny x nz orthohexagonal cells (1, sqrt3, c),
/// 4 grains each (layer A at z = 0, layer B at z = c/2).
std::vector<Vec<3>> hcp(int nx, int ny, int nz, Vec<3>& lengths) {
  const double s3 = std::sqrt(3.0), c = std::sqrt(8.0 / 3.0);
  const double basis[4][3] = {
      {0, 0, 0}, {0.5, s3 / 2, 0}, {0.5, s3 / 6, c / 2}, {0, s3 / 6 + s3 / 2, c / 2}};
  std::vector<Vec<3>> p;
  for (int x = 0; x < nx; ++x)
    for (int y = 0; y < ny; ++y)
      for (int z = 0; z < nz; ++z)
        for (const auto& b : basis)
          p.push_back(Vec<3>(x + b[0], y * s3 + b[1], z * c + b[2]));
  lengths = Vec<3>(nx, ny * s3, nz * c);
  return p;
}

/// Uniform random points (an ideal gas: no exclusion, hence no order at any density).
std::vector<Vec<3>> gas(std::size_t n, double side, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, side);
  std::vector<Vec<3>> p(n);
  for (auto& r : p)
    r = Vec<3>(u(rng), u(rng), u(rng));
  return p;
}

Vec<3> direction(double theta, double phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

void expect_complex_near(std::complex<double> a, std::complex<double> b, double tol) {
  EXPECT_NEAR(a.real(), b.real(), tol);
  EXPECT_NEAR(a.imag(), b.imag(), tol);
}

} // namespace

TEST(BondOrderHarmonics, ClosedFormsWithCondonShortleyPhase) {
  const double th = 0.7, ph = 2.1;
  const std::complex<double> e1 = std::polar(1.0, ph), e2 = std::polar(1.0, 2 * ph);
  const Vec<3> n = 3.5 * direction(th, ph); // the length must not matter
  auto y0 = spherical_harmonics(0, n);
  ASSERT_EQ(y0.size(), 1u);
  expect_complex_near(y0[0], 1 / std::sqrt(4 * kPi), 1e-14);
  auto y1 = spherical_harmonics(1, n); // index m + 1
  expect_complex_near(y1[1], std::sqrt(3 / (4 * kPi)) * std::cos(th), 1e-14);
  expect_complex_near(y1[2], -std::sqrt(3 / (8 * kPi)) * std::sin(th) * e1, 1e-14);
  expect_complex_near(y1[0], std::sqrt(3 / (8 * kPi)) * std::sin(th) * std::conj(e1), 1e-14);
  auto y2 = spherical_harmonics(2, n); // index m + 2
  const double s = std::sin(th), c = std::cos(th);
  expect_complex_near(y2[4], 0.25 * std::sqrt(15 / (2 * kPi)) * s * s * e2, 1e-14);
  expect_complex_near(y2[1], 0.5 * std::sqrt(15 / (2 * kPi)) * s * c * std::conj(e1), 1e-14);
  expect_complex_near(y2[2], 0.25 * std::sqrt(5 / kPi) * (3 * c * c - 1), 1e-14);
}

TEST(BondOrderHarmonics, AdditionTheorem) {
  // sum_m Y_lm(a) Y_lm(b)^* = (2l+1)/(4 pi) P_l(a.b): checks every m, signs included.
  std::mt19937_64 rng(7);
  std::normal_distribution<double> g;
  for (int trial = 0; trial < 20; ++trial) {
    const Vec<3> a(g(rng), g(rng), g(rng)), b(g(rng), g(rng), g(rng));
    const double cg = a.normalized().dot(b.normalized());
    for (int l = 0; l <= 10; ++l) {
      auto ya = spherical_harmonics(l, a), yb = spherical_harmonics(l, b);
      std::complex<double> s = 0;
      for (std::size_t k = 0; k < ya.size(); ++k)
        s += ya[k] * std::conj(yb[k]);
      const double expect = (2 * l + 1) / (4 * kPi) * std::legendre(static_cast<unsigned>(l), cg);
      EXPECT_NEAR(s.real(), expect, 1e-12) << "l = " << l;
      EXPECT_NEAR(s.imag(), 0.0, 1e-12) << "l = " << l;
    }
  }
  // On the axis (phi undefined): only m = 0 survives.
  auto y = spherical_harmonics(6, Vec<3>(0, 0, -2));
  for (int m = -6; m <= 6; ++m) {
    if (m != 0) {
      EXPECT_EQ(std::abs(y[static_cast<std::size_t>(m + 6)]), 0.0);
    }
  }
  EXPECT_THROW(spherical_harmonics(6, Vec<3>::Zero()), Error);
}

TEST(BondOrder, PerfectFcc) {
  Vec<3> L;
  const auto p = fcc(3, L); // 108 grains, L = 4.24 > 2 d_c
  for (const double dc : {1.35, 1.40}) {
    SCOPED_TRACE("d_c = " + std::to_string(dc));
    const auto r = bond_order_periodic(p, L, {dc, 0.5, 7});
    ASSERT_EQ(r.grains.size(), p.size());
    for (const auto& g : r.grains) {
      EXPECT_EQ(g.n_bonds, 12);
      EXPECT_NEAR(g.q4, 0.191, 1e-3);
      EXPECT_NEAR(g.q6, 0.575, 1e-3);
      // Closed forms: Q4 = sqrt(7/192), Q6 = sqrt(169/512) = 13/(16 sqrt 2).
      EXPECT_NEAR(g.q4, std::sqrt(7.0 / 192.0), 1e-12);
      EXPECT_NEAR(g.q6, std::sqrt(169.0 / 512.0), 1e-12);
      EXPECT_EQ(g.n_crystalline_bonds, 12);
      EXPECT_TRUE(g.crystalline);
      // [AR] app. D windows: fcc-like, not hcp-like.
      const auto w = windows_containing(g.q4, g.q6, order_windows());
      ASSERT_EQ(w.size(), 1u);
      EXPECT_EQ(order_windows()[w[0]].kind, LocalOrder::fcc);
    }
    EXPECT_DOUBLE_EQ(r.tally.z(), 12.0);
    EXPECT_DOUBLE_EQ(r.tally.z_cr(), 12.0);
    EXPECT_DOUBLE_EQ(r.tally.x_cr(), 1.0);
    EXPECT_NEAR(r.tally.q6_loc(), std::sqrt(169.0 / 512.0), 1e-12);
    EXPECT_NEAR(r.tally.q6_loc_cr(), std::sqrt(169.0 / 512.0), 1e-12);
    // A single crystal: every grain sees the same orientation, global = local.
    EXPECT_NEAR(r.tally.q6_global(), std::sqrt(169.0 / 512.0), 1e-12);
    ASSERT_EQ(r.clusters.sizes.size(), 1u);
    EXPECT_EQ(r.clusters.sizes[0], static_cast<std::int64_t>(p.size()));
    EXPECT_DOUBLE_EQ(r.clusters.mass_average_size, static_cast<double>(p.size()));
  }
}

TEST(BondOrder, PerfectHcp) {
  Vec<3> L;
  const auto p = hcp(4, 3, 3, L); // 144 grains, L = (4, 5.20, 4.90)
  for (const double dc : {1.35, 1.40}) {
    SCOPED_TRACE("d_c = " + std::to_string(dc));
    const auto r = bond_order_periodic(p, L, {dc, 0.5, 7});
    for (const auto& g : r.grains) {
      EXPECT_EQ(g.n_bonds, 12);
      EXPECT_NEAR(g.q4, 0.097, 1e-3);
      EXPECT_NEAR(g.q6, 0.485, 1e-3);
      EXPECT_NEAR(g.q4, 7.0 / 72.0, 1e-12); // Q4(hcp) = 7/72 exactly
      EXPECT_EQ(g.n_crystalline_bonds, 12);
      EXPECT_TRUE(g.crystalline);
      const auto w = windows_containing(g.q4, g.q6, order_windows());
      ASSERT_EQ(w.size(), 1u);
      EXPECT_EQ(order_windows()[w[0]].kind, LocalOrder::hcp);
    }
    EXPECT_DOUBLE_EQ(r.tally.x_cr(), 1.0);
    // The 12 neighbours have D3h symmetry about c (z): 3-fold axis and mirror z = 0 leave
    // only m = 0 and +-6 of l = 6, unchanged by the 60 degree turn between A and B layers,
    // so both layers have the same qbar_6m and the global Q6 equals the local one.
    EXPECT_NEAR(r.tally.q6_global(), r.grains[0].q6, 1e-12);
    ASSERT_EQ(r.clusters.sizes.size(), 1u);
    EXPECT_EQ(r.clusters.sizes[0], static_cast<std::int64_t>(p.size()));
  }
}

TEST(BondOrder, RotationalInvariance) {
  // The 12 bonds of one FCC grain, then the same bonds rotated by random rotations.
  Vec<3> L;
  const auto hoods = periodic_neighborhoods(fcc(3, L), L, 1.4);
  const auto& bonds = hoods[13].bonds;
  ASSERT_EQ(bonds.size(), 12u);
  std::mt19937_64 rng(2024);
  std::normal_distribution<double> g;
  for (int trial = 0; trial < 10; ++trial) {
    const Eigen::Quaterniond rot = Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)).normalized();
    std::vector<Vec<3>> turned;
    for (const auto& b : bonds)
      turned.push_back(rot * b);
    for (int l = 1; l <= 10; ++l) {
      const auto a = local_q(std::span<const Vec<3>>(bonds), l);
      const auto b = local_q(std::span<const Vec<3>>(turned), l);
      EXPECT_NEAR(a.Q, b.Q, 1e-12) << "l = " << l;
    }
    // The rotation does change the coefficients (else the test would prove nothing)...
    const auto a6 = local_q(std::span<const Vec<3>>(bonds), 6);
    const auto b6 = local_q(std::span<const Vec<3>>(turned), 6);
    double diff = 0;
    for (std::size_t k = 0; k < a6.q.size(); ++k)
      diff += std::abs(a6.q[k] - b6.q[k]);
    EXPECT_GT(diff, 1e-3);
    // ... and so the correlation of eq. (34) between the two copies (rotated crystals).
    EXPECT_LT(bond_correlation(a6.normalized(), b6.normalized()), 1.0 - 1e-6);
  }
}

TEST(BondOrder, LocalQDoesNotDependOnBondOrder) {
  const auto hoods = periodic_neighborhoods(gas(500, 7.0, 3), Vec<3>::Constant(7.0), 1.4);
  std::mt19937_64 rng(11);
  for (const auto& h : hoods) {
    const auto ref = local_q(h, 6);
    std::vector<std::size_t> perm(h.bonds.size());
    for (std::size_t k = 0; k < perm.size(); ++k)
      perm[k] = k;
    std::shuffle(perm.begin(), perm.end(), rng);
    BondNeighborhood s{h.id, {}, {}};
    for (auto k : perm) {
      s.bonds.push_back(h.bonds[k]);
      s.neighbor_ids.push_back(h.neighbor_ids[k]);
    }
    const auto shuffled = local_q(s, 6);
    ASSERT_EQ(shuffled.q, ref.q); // bitwise: summed in ascending neighbour id
  }
}

TEST(BondOrder, RandomGasHasNoOrder) {
  // Ideal gas (uniform random points) at the coordination of the [AR] packings: 13 bonds per
  // grain within d_c = 1.4 (table II: Z = 12.4-13.2), i.e. number density
  // 13 / (4 pi d_c^3 / 3) = 1.13. The points overlap freely, so there is no order.
  const std::size_t n = 4000;
  const double dc = 1.4, rho = 13.0 / (4.0 * kPi / 3.0 * dc * dc * dc);
  const double side = std::cbrt(static_cast<double>(n) / rho);
  const auto r = bond_order_periodic(gas(n, side, 42), Vec<3>::Constant(side), {dc, 0.5, 7});
  EXPECT_NEAR(r.tally.z(), 13.0, 0.3); // Poisson: sd of the mean 13^(1/2)/4000^(1/2) ~ 0.06
  // Global Q6. For N_B independent isotropic bond directions, E|sum_b Y_6m|^2 = N_B/(4 pi)
  // for each m (int |Y|^2 dOmega = 1), so E[Q6^2] = 4 pi/13 * 13/(4 pi N_B) = 1/N_B, and
  // N_B Q6^2 is close to chi^2_13 / 13 (13 real Gaussian components, Y_6,-m = (-1)^m Y_6m^*).
  // Bounds 0.1 and 3 (in units of N_B^-1/2) are passed with probabilities 1 - 1e-11 and
  // 1 - 1e-14 (chi^2_13 < 0.13, > 117). N_B counts undirected bonds: the sum meets each bond
  // from both ends with the same Y_6m (even l), which leaves Q6 unchanged.
  const double nb = static_cast<double>(r.tally.n_bonds) / 2.0;
  const double q6 = r.tally.q6_global();
  EXPECT_GT(q6 * std::sqrt(nb), 0.1);
  EXPECT_LT(q6 * std::sqrt(nb), 3.0);
  // Local Q6: the same argument for the N_b(i) ~ 13 bonds of one grain gives
  // E[Q6(i)^2] = 1/N_b, rms 0.28 (vs 0.39 in [AR]'s RCP, table II, and 0.575 in fcc).
  EXPECT_GT(r.tally.q6_loc(), 0.2);
  EXPECT_LT(r.tally.q6_loc(), 0.35);
  // Crystalline bonds. Were qbar(i), qbar(j) independent isotropic unit vectors of R^13, the
  // product of eq. (34) (real) would be a cosine with density ~ (1 - x^2)^5, and
  // P(|x| >= 0.5) = 0.069. Neighbours share their bond (Y_6(n_ij) = Y_6(n_ji)) and some of
  // their other neighbours, which correlates them a little: measured 0.091-0.094 (seeds 1, 2,
  // 3, 42; sd over ~26000 bonds ~0.002). A crystal gives 1, [AR]'s RCP Z_cr/Z = 2.9/12.4 =
  // 0.23 (table II). Bounds: 0.05 < fraction < 0.15.
  const double bond_fraction =
      static_cast<double>(r.tally.n_crystalline_bonds) / static_cast<double>(r.tally.n_bonds);
  EXPECT_LT(bond_fraction, 0.15);
  EXPECT_GT(bond_fraction, 0.05);
  // Crystalline grains need >= 7 crystalline bonds out of ~13: for independent bonds with
  // p = 0.09, P(Bin(13, 0.09) >= 7) = 5e-5; the correlations raise it (measured 0 to 0.0015).
  // Bound 0.01 (a crystal gives 1, [AR]'s RCP x_cr = 0.08).
  EXPECT_LT(r.tally.x_cr(), 0.01);
  EXPECT_LT(r.clusters.mass_average_size, 5.0); // a few isolated grains at most
}

TEST(BondOrder, LoneBondIsTriviallyCrystalline) {
  // A pair bonded only to each other: qbar(i) = qbar(j) (Y_6 is even), so the bond is
  // "crystalline" - the reason eq. (34) only means something with the >= 7 rule.
  BondNeighborhood a{5, {Vec<3>(0.3, 0.4, 1.0)}, {9}}, b{9, {Vec<3>(-0.3, -0.4, -1.0)}, {5}};
  QBarTable t(6);
  t.insert(a.id, local_q(a, 6).normalized());
  t.insert(b.id, local_q(b, 6).normalized());
  EXPECT_NEAR(bond_correlation(t.find(5), t.find(9)), 1.0, 1e-14);
  EXPECT_EQ(crystalline_neighbors(a, t), (std::vector<GlobalId>{9}));
  EXPECT_EQ(crystalline_neighbors(b, t), (std::vector<GlobalId>{5}));
  // No bond: Q = 0, qbar = 0, and no crystalline bond with anything.
  BondNeighborhood lone{7, {}, {}};
  const auto q = local_q(lone, 6);
  EXPECT_EQ(q.n_bonds, 0);
  EXPECT_EQ(q.Q, 0.0);
  EXPECT_EQ(bond_correlation(q.normalized(), t.find(5)), 0.0);
  // Re-inserting replaces the entry in place.
  t.insert(9, q.normalized());
  EXPECT_EQ(t.size(), 2u);
  EXPECT_EQ(bond_correlation(t.find(5), t.find(9)), 0.0);
  EXPECT_TRUE(t.find(123).empty());
}

TEST(BondOrder, StagedTwoRankRecipeMatchesSerial) {
  // The driver's recipe on two fake ranks (split at x = L/2): each computes q for its owned
  // grains, the owners' qbar are exchanged for the ghosts, each counts crystalline bonds of
  // its owned grains, tallies are packed, summed (the all-reduce) and unpacked.
  const double side = 12.0, dc = 1.4;
  const auto p = gas(2000, side, 5);
  const Vec<3> L = Vec<3>::Constant(side);
  const auto hoods = periodic_neighborhoods(p, L, dc);
  const auto serial = bond_order_periodic(p, L, {dc, 0.5, 7});
  auto rank_of = [&](std::size_t i) { return p[i][0] < side / 2 ? 0 : 1; };

  std::vector<QBarTable> tables(2, QBarTable(6));
  std::vector<std::vector<LocalBondOrder>> q6(2);
  for (std::size_t i = 0; i < p.size(); ++i) { // stage 1 (owned grains)
    auto q = local_q(hoods[i], 6);
    tables[static_cast<std::size_t>(rank_of(i))].insert(hoods[i].id, q.normalized());
  }
  for (int rk = 0; rk < 2; ++rk) { // halo: the other rank's qbar for ghosts within d_c
    const auto& other = tables[static_cast<std::size_t>(1 - rk)];
    auto& mine = tables[static_cast<std::size_t>(rk)];
    const std::size_t n13 = 13;
    for (std::size_t k = 0; k < other.ids().size(); ++k) {
      const GlobalId id = other.ids()[k];
      bool needed = false; // is it a neighbour of one of my grains?
      for (GlobalId j : hoods[static_cast<std::size_t>(id)].neighbor_ids)
        needed = needed || rank_of(static_cast<std::size_t>(j)) == rk;
      if (!needed)
        continue;
      std::span<const std::complex<double>> v(other.values().data() + k * n13, n13);
      if (mine.find(id).empty())
        mine.insert(id, v);
    }
  }
  std::vector<double> sums;
  std::vector<GlobalId> cryst;
  std::vector<std::pair<GlobalId, GlobalId>> cbonds;
  for (int rk = 0; rk < 2; ++rk) { // stages 2-3 per rank
    BondOrderTally t;
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (rank_of(i) != rk)
        continue;
      const auto cn = crystalline_neighbors(hoods[i], tables[static_cast<std::size_t>(rk)]);
      t.add(local_q(hoods[i], 6), static_cast<int>(cn.size()));
      EXPECT_EQ(static_cast<int>(cn.size()), serial.grains[i].n_crystalline_bonds);
      if (cn.size() >= 7) {
        cryst.push_back(hoods[i].id);
        for (GlobalId j : cn)
          cbonds.emplace_back(hoods[i].id, j); // both directions: fine
      }
    }
    const auto packed = t.packed();
    if (sums.empty())
      sums.assign(packed.size(), 0.0);
    for (std::size_t k = 0; k < packed.size(); ++k)
      sums[k] += packed[k]; // "MPI_SUM"
  }
  const auto total = BondOrderTally::unpacked(sums);
  EXPECT_EQ(total.n_grains, serial.tally.n_grains);
  EXPECT_EQ(total.n_bonds, serial.tally.n_bonds);
  EXPECT_EQ(total.n_crystalline_bonds, serial.tally.n_crystalline_bonds);
  EXPECT_EQ(total.n_crystalline_grains, serial.tally.n_crystalline_grains);
  EXPECT_NEAR(total.q6_global(), serial.tally.q6_global(), 1e-12);
  EXPECT_NEAR(total.q6_loc(), serial.tally.q6_loc(), 1e-12);
  EXPECT_NEAR(total.q6_loc_cr(), serial.tally.q6_loc_cr(), 1e-12);
  std::shuffle(cryst.begin(), cryst.end(), std::mt19937_64(1)); // gather order is arbitrary
  const auto clusters = crystalline_clusters(cryst, cbonds);
  EXPECT_EQ(clusters.sizes, serial.clusters.sizes);
  EXPECT_DOUBLE_EQ(clusters.mass_average_size, serial.clusters.mass_average_size);
  // A missing ghost qbar is reported, not silently skipped.
  BondOrderTally m;
  m.merge(serial.tally);
  EXPECT_EQ(m.n_bonds, serial.tally.n_bonds);
  QBarTable empty(6);
  EXPECT_THROW(crystalline_neighbors(hoods[0], empty), Error);
}

TEST(BondOrder, ClustersByUnionFind) {
  // Crystalline grains 1..7 and 10; bonds: triangle 1-2-3 (with a repeated, reversed edge),
  // pair 4-5 (listed from both ends), 6-99 where 99 is not crystalline (ignored), 7 and 10
  // isolated. Clusters {1,2,3}, {4,5}, {6}, {7}, {10}: sum s = 8, sum s^2 = 9+4+1+1+1 = 16,
  // <n_cr> = 2.
  const std::vector<GlobalId> grains = {10, 7, 3, 1, 6, 2, 5, 4};
  const std::vector<std::pair<GlobalId, GlobalId>> bonds = {{1, 2}, {2, 3}, {3, 1},  {2, 1},
                                                            {4, 5}, {5, 4}, {6, 99}, {7, 7}};
  const auto c = crystalline_clusters(grains, bonds);
  EXPECT_EQ(c.sizes, (std::vector<std::int64_t>{3, 2, 1, 1, 1}));
  EXPECT_DOUBLE_EQ(c.mass_average_size, 2.0);
  // Labels: by size, ties by smallest member id -> {1,2,3}=0, {4,5}=1, {6}=2, {7}=3, {10}=4.
  EXPECT_EQ(c.cluster_of, (std::vector<std::size_t>{4, 3, 0, 0, 2, 0, 1, 1}));
  // One chain 0-1-...-9 plus 10 singletons: (100 + 10) / 20 = 5.5.
  std::vector<GlobalId> g2;
  std::vector<std::pair<GlobalId, GlobalId>> b2;
  for (GlobalId i = 0; i < 20; ++i)
    g2.push_back(i);
  for (GlobalId i = 0; i < 9; ++i)
    b2.emplace_back(i, i + 1);
  EXPECT_DOUBLE_EQ(crystalline_clusters(g2, b2).mass_average_size, 5.5);
  EXPECT_EQ(crystalline_clusters({}, {}).mass_average_size, 0.0);
  EXPECT_THROW(crystalline_clusters({1, 2, 1}, {}), Error);
}

TEST(BondOrder, WindowsOfTablesVIIandVIII) {
  const auto all = order_windows();
  ASSERT_EQ(all.size(), 14u);
  for (const auto& w : all)
    EXPECT_EQ(w.half_width, 0.05);
  // fcc and hcp centres ([AR] app. D) fall in their own windows only.
  auto kinds = [&](double q4, double q6, std::span<const OrderWindow> ws) {
    std::vector<std::string> k;
    for (auto i : windows_containing(q4, q6, ws))
      k.emplace_back(to_string(ws[i].kind));
    return k;
  };
  EXPECT_EQ(kinds(0.191, 0.574, all), (std::vector<std::string>{"fcc"}));
  EXPECT_EQ(kinds(0.097, 0.485, all), (std::vector<std::string>{"hcp"}));
  EXPECT_TRUE(kinds(0.6, 0.1, all).empty());
  // Edges (closed windows): just inside / just outside the fcc window.
  EXPECT_EQ(kinds(0.191 + 0.0499, 0.574 - 0.0499, all), (std::vector<std::string>{"fcc"}));
  EXPECT_TRUE(kinds(0.191 + 0.0501, 0.574, all).empty());
  EXPECT_TRUE(kinds(0.191, 0.574 - 0.0501, all).empty());
  // Dense sample F (table VII) at d_c = 1.2a: dis centre (0.16, 0.45); it overlaps hcp.
  const auto f12 = windows_for(AsteSample::F, 1.2);
  ASSERT_EQ(f12.size(), 3u);
  EXPECT_EQ(f12[0].kind, LocalOrder::disordered);
  EXPECT_DOUBLE_EQ(f12[0].q4, 0.16);
  EXPECT_DOUBLE_EQ(f12[0].q6, 0.45);
  EXPECT_EQ(kinds(0.16, 0.45, f12), (std::vector<std::string>{"dis"}));
  EXPECT_EQ(kinds(0.13, 0.46, f12), (std::vector<std::string>{"dis", "hcp"}));
  // Table VIII: Aste D at 1.4a is (0.11, 0.36); Aste B (loose) at 1.1a is (0.30, 0.45).
  const auto d14 = windows_for(AsteSample::D, 1.4);
  EXPECT_DOUBLE_EQ(d14[0].q4, 0.11);
  EXPECT_DOUBLE_EQ(d14[0].q6, 0.36);
  EXPECT_EQ(kinds(0.11, 0.36, d14), (std::vector<std::string>{"dis"}));
  const auto b11 = windows_for(AsteSample::B, 1.1);
  EXPECT_EQ(kinds(0.30, 0.45, b11), (std::vector<std::string>{"dis"}));
  EXPECT_TRUE(kinds(0.30, 0.45, f12).empty());
  // Which experimental sample each [AR] state is compared with.
  EXPECT_EQ(aste_sample_compared_with("A'"), AsteSample::F);
  EXPECT_EQ(aste_sample_compared_with("C"), AsteSample::F);
  EXPECT_EQ(aste_sample_compared_with("B"), AsteSample::D);
  EXPECT_EQ(aste_sample_compared_with("D"), AsteSample::B);
  EXPECT_THROW(aste_sample_compared_with("Z"), InputError);
  EXPECT_THROW(windows_for(AsteSample::F, 1.35), InputError);
  EXPECT_THROW(windows_for(AsteSample::any, 1.2), InputError);
}

TEST(BondOrder, RejectsBadInput) {
  BondNeighborhood twice{1, {Vec<3>(1, 0, 0), Vec<3>(-1, 0, 0)}, {2, 2}};
  EXPECT_THROW(local_q(twice, 6), Error);
  BondNeighborhood mismatch{1, {Vec<3>(1, 0, 0)}, {}};
  EXPECT_THROW(local_q(mismatch, 6), Error);
  BondNeighborhood zero{1, {Vec<3>::Zero()}, {2}};
  EXPECT_THROW(local_q(zero, 6), Error);
  EXPECT_THROW(GlobalQlSum(5), Error);
  EXPECT_THROW(periodic_neighborhoods({Vec<3>::Zero()}, Vec<3>::Constant(2.0), 1.0), Error);
  QBarTable t(6);
  EXPECT_THROW(t.insert(3, QlmVector(9)), Error);
  EXPECT_THROW(BondOrderTally::unpacked(std::vector<double>(5)), Error);
}
