// Event-driven hard-sphere MD (dynamics/hard_sphere_md.h, docs/event-driven.md): no overlap,
// conservation laws, Carnahan-Starling equation of state, Lubachevsky-Stillinger growth to an
// exact solid fraction, disks, the all-pairs fallback of small boxes, two-body closed forms.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <vector>

#include "granpack/core/error.h"
#include "granpack/dynamics/hard_sphere_md.h"

namespace granpack {
namespace {

template <int dim> struct Config {
  Vec<dim> box;
  std::vector<Vec<dim>> x;
  std::vector<double> r, m;
  std::vector<Vec<dim>> v;
};

/// Maxwellian velocities with zero total momentum and kT = 1 (unit masses unless set).
template <int dim> void thermalise(Config<dim>& c, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  const std::size_t n = c.x.size();
  c.v.assign(n, Vec<dim>::Zero());
  Vec<dim> p = Vec<dim>::Zero();
  double mass = 0;
  for (std::size_t i = 0; i < n; ++i) {
    for (int a = 0; a < dim; ++a)
      c.v[i][a] = g(rng) / std::sqrt(c.m[i]);
    p += c.m[i] * c.v[i];
    mass += c.m[i];
  }
  double k = 0;
  for (std::size_t i = 0; i < n; ++i) {
    c.v[i] -= p / mass;
    k += 0.5 * c.m[i] * c.v[i].squaredNorm();
  }
  const double f = std::sqrt(0.5 * dim * static_cast<double>(n) / k);
  for (auto& v : c.v)
    v *= f;
}

/// FCC lattice of nc^3 conventional cells (4 nc^3 unit-diameter spheres) at solid fraction phi.
Config<3> fcc(int nc, double phi, std::uint64_t seed) {
  Config<3> c;
  const int n = 4 * nc * nc * nc;
  const double l = std::cbrt(n * std::numbers::pi / 6.0 / phi);
  const double a = l / nc;
  c.box = Vec<3>::Constant(l);
  const double basis[4][3] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
  for (int i = 0; i < nc; ++i)
    for (int j = 0; j < nc; ++j)
      for (int k = 0; k < nc; ++k)
        for (const auto& b : basis)
          c.x.push_back(a * Vec<3>(i + b[0] + 0.25, j + b[1] + 0.25, k + b[2] + 0.25));
  c.r.assign(c.x.size(), 0.5);
  c.m.assign(c.x.size(), 1.0);
  thermalise(c, seed);
  return c;
}

/// Square lattice of nc^2 unit-diameter disks at area fraction phi.
Config<2> square(int nc, double phi, std::uint64_t seed) {
  Config<2> c;
  const int n = nc * nc;
  const double l = std::sqrt(n * std::numbers::pi / 4.0 / phi);
  const double a = l / nc;
  c.box = Vec<2>::Constant(l);
  for (int i = 0; i < nc; ++i)
    for (int j = 0; j < nc; ++j)
      c.x.push_back(a * Vec<2>(i + 0.5, j + 0.5));
  c.r.assign(c.x.size(), 0.5);
  c.m.assign(c.x.size(), 1.0);
  thermalise(c, seed);
  return c;
}

template <int dim> HardSphereMD<dim> make(const Config<dim>& c) {
  return HardSphereMD<dim>(c.box, c.x, c.r, c.m, c.v);
}

template <int dim> double momentum_scale(const HardSphereMD<dim>& md) {
  double s = 0;
  for (std::size_t i = 0; i < md.size(); ++i)
    s += md.masses()[i] * md.velocities()[i].norm();
  return s;
}

/// Carnahan-Starling compressibility factor Z = PV/(NkT) of the hard-sphere fluid.
double carnahan_starling(double eta) {
  return (1 + eta + eta * eta - eta * eta * eta) / std::pow(1 - eta, 3);
}

/// Z = P V / (N kT), kT = 2K / (dim N).
template <int dim> double compressibility(const HardSphereMD<dim>& md) {
  return md.pressure() * md.box().prod() * dim / (2 * md.kinetic_energy());
}

// ---------------------------------------------------------------------------------------

TEST(HardSphereMD, NeverOverlapsWhileMeltingFcc) {
  auto md = make(fcc(5, 0.45, 1)); // 500 spheres
  const auto n = static_cast<std::int64_t>(md.size());
  EXPECT_GE(md.min_relative_gap(), 0.0);
  for (int k = 0; k < 10; ++k) {
    md.run_collisions(5 * n);
    EXPECT_GE(md.min_relative_gap(), -1e-10) << "after " << md.collisions() << " collisions";
    for (const auto& x : md.positions())
      for (int a = 0; a < 3; ++a) {
        EXPECT_GE(x[a], 0.0);
        EXPECT_LT(x[a], md.box()[a]);
      }
  }
  EXPECT_EQ(md.collisions(), 50 * n);
  EXPECT_GT(md.time(), 0.0);
}

TEST(HardSphereMD, ConservesEnergyAndMomentumPolydisperse) {
  // Radii in [0.4, 0.5] and masses ~ r^3 on an FCC lattice made for unit diameters.
  auto c = fcc(5, 0.45, 2);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.4, 0.5);
  for (std::size_t i = 0; i < c.r.size(); ++i) {
    c.r[i] = u(rng);
    c.m[i] = 8 * std::pow(c.r[i], 3);
  }
  thermalise(c, 4);
  auto md = make(c);
  const double k0 = md.kinetic_energy();
  const Vec<3> p0 = md.momentum();
  md.run_collisions(100 * static_cast<std::int64_t>(md.size()));
  EXPECT_NEAR(md.kinetic_energy() / k0, 1.0, 1e-10);
  EXPECT_LE((md.momentum() - p0).norm(), 1e-12 * momentum_scale(md));
  EXPECT_GE(md.min_relative_gap(), -1e-10);
}

TEST(HardSphereMD, PressureFollowsCarnahanStarling) {
  // Expected Z = PV/(NkT): 3.9738 at eta = 0.30, 9.3847 at eta = 0.45 (CS is within ~0.5 % of
  // simulations there); 864 spheres, 50 collisions per grain to equilibrate after melting the
  // lattice, then the pressure averaged over 300 collisions per grain.
  const double expected[2] = {3.9738, 9.3847};
  const double eta[2] = {0.30, 0.45};
  for (int k = 0; k < 2; ++k) {
    EXPECT_NEAR(carnahan_starling(eta[k]), expected[k], 1e-4);
    auto md = make(fcc(6, eta[k], 10 + k));
    const auto n = static_cast<std::int64_t>(md.size());
    md.run_collisions(50 * n);
    md.reset_pressure();
    md.run_collisions(300 * n);
    const double z = compressibility(md);
    std::printf("[          ] eta = %.2f: Z = %.4f (Carnahan-Starling %.4f)\n", eta[k], z,
                expected[k]);
    EXPECT_NEAR(z / expected[k], 1.0, 0.02) << "eta = " << eta[k];
  }
}

TEST(HardSphereMD, IdealGasLimitOfPressure) {
  // No collisions in the averaging window: P = 2K/(dim V) = N kT / V exactly.
  auto md = make(fcc(3, 0.01, 5));
  md.reset_pressure();
  EXPECT_NEAR(md.pressure() * md.box().prod() / static_cast<double>(md.size()), 1.0, 1e-12);
}

TEST(HardSphereMD, LubachevskyStillingerGrowthStopsExactlyAtTarget) {
  auto md = make(fcc(5, 0.45, 6));
  const auto n = static_cast<std::int64_t>(md.size());
  // The grid the constructor builds for the diameters (the fixed-radius run that follows
  // replaces it by the coarser grid of the neighbour lists' centres).
  const auto cells_before = md.cells_per_axis();
  md.run_collisions(20 * n);
  const double k0 = md.kinetic_energy();
  const std::int64_t c0 = md.collisions();
  const double t0 = md.time();
  int calls = 0;
  double worst_gap = 1;
  md.grow(0.55, 0.05, 1.0, [&](const HardSphereMD<3>& m) {
    ++calls;
    worst_gap = std::min(worst_gap, m.min_relative_gap());
  });
  EXPECT_NEAR(md.solid_fraction(), 0.55, 1e-12);
  EXPECT_GE(md.min_relative_gap(), -1e-10);
  EXPECT_GE(worst_gap, -1e-10);
  EXPECT_GT(calls, 0);
  // Radii grew by (0.55/0.45)^(1/3) at relative rate 0.05 per unit time.
  const double g = std::cbrt(0.55 / 0.45);
  EXPECT_NEAR(md.time() - t0, (g - 1) / 0.05, 1e-9);
  for (double r : md.radii())
    EXPECT_NEAR(r, 0.5 * g, 1e-14);
  EXPECT_GT(md.collisions() - c0, n);
  // The grid was rebuilt coarser as the diameters outgrew the cells.
  EXPECT_LT(md.cells_per_axis()[0], cells_before[0]);
  // Rescaled to the initial kinetic energy at most n collisions ago: still of that order.
  EXPECT_NEAR(md.kinetic_energy() / k0, 1.0, 0.5);
  // Fixed-radius dynamics resumes from the grown state without overlap, conserving energy.
  const double k1 = md.kinetic_energy();
  md.run_collisions(10 * n);
  EXPECT_NEAR(md.kinetic_energy() / k1, 1.0, 1e-10);
  EXPECT_GE(md.min_relative_gap(), -1e-10);
  EXPECT_NEAR(md.solid_fraction(), 0.55, 1e-12);
}

/// Positions, velocities and radii equal bit for bit.
template <int dim> void expect_same_state(const HardSphereMD<dim>& a, const HardSphereMD<dim>& b) {
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(a.collisions(), b.collisions());
  EXPECT_EQ(a.time(), b.time());
  std::size_t differ = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    differ += a.positions()[i] != b.positions()[i] || a.velocities()[i] != b.velocities()[i] ||
              a.radii()[i] != b.radii()[i];
  EXPECT_EQ(differ, 0u) << "grains differ";
  EXPECT_EQ(a.pressure(), b.pressure());
}

TEST(HardSphereMD, GrowthInPiecesAndSavedStatesContinueBitForBit) {
  // What a checkpoint inside ed_gas / ls_compress relies on (docs/long-jobs.md): stopping the
  // engine after any collision, saving and restoring it, changes nothing in the trajectory.
  auto whole = make(fcc(5, 0.45, 8));
  auto split = make(fcc(5, 0.45, 8));
  const auto n = static_cast<std::int64_t>(whole.size());
  whole.reset_pressure();
  split.reset_pressure();
  whole.run_collisions(30 * n);
  split.run_collisions(1234);
  split = HardSphereMD<3>::restore_state(split.save_state());
  split.run_collisions(30 * n - 1234);
  expect_same_state(whole, split);

  whole.grow(0.56, 0.02, 0.5);
  split.begin_growth(0.56, 0.02, 0.5);
  int pieces = 0, restores = 0;
  while (!split.continue_growth(997)) {
    if (++pieces % 3 == 0) {
      split = HardSphereMD<3>::restore_state(split.save_state());
      ++restores;
    }
  }
  EXPECT_GT(restores, 3);
  EXPECT_FALSE(split.growing());
  expect_same_state(whole, split);
  // And fixed-radius dynamics after the growth.
  whole.run_collisions(5 * n);
  split.run_collisions(5 * n);
  expect_same_state(whole, split);
}

TEST(HardSphereMD, RestoreRefusesWhatIsNotASavedState) {
  auto md = make(square(8, 0.4, 2));
  auto bytes = md.save_state();
  EXPECT_THROW(HardSphereMD<3>::restore_state(bytes), Error); // another dimension
  auto cut = bytes;
  cut.resize(cut.size() / 2);
  EXPECT_THROW(HardSphereMD<2>::restore_state(cut), Error);
  auto bad = bytes;
  bad[0] ^= 1;
  EXPECT_THROW(HardSphereMD<2>::restore_state(bad), Error);
  EXPECT_NO_THROW(HardSphereMD<2>::restore_state(bytes));
}

TEST(HardSphereMD, GrowRejectsImpossibleTargets) {
  auto md = make(fcc(2, 0.3, 7));          // 32 spheres, box 3.8 diameters
  EXPECT_THROW(md.grow(0.2, 0.1), Error);  // shrinking
  EXPECT_THROW(md.grow(0.5, -1.0), Error); // bad rate
  EXPECT_THROW(md.grow(2.5, 0.1), Error);  // diameters would not fit twice in the box
}

TEST(HardSphereMD, GrowthThrowsWhenItJamsBelowTheTarget) {
  // Fast growth jams 256 spheres near phi 0.64, far below 0.75: grow() must stop and say so
  // (not loop forever with the clock frozen), leaving a usable packing at fixed radii.
  auto md = make(fcc(4, 0.45, 13));
  md.run_collisions(20 * static_cast<std::int64_t>(md.size()));
  EXPECT_THROW(md.grow(0.75, 0.2), Error);
  EXPECT_GT(md.solid_fraction(), 0.6);
  EXPECT_LT(md.solid_fraction(), 0.70);
  EXPECT_GE(md.min_relative_gap(), -1e-10);
  EXPECT_NO_THROW(md.run_collisions(100));
  EXPECT_GE(md.min_relative_gap(), -1e-10);
}

TEST(HardSphereMD, DisksNeverOverlapAndConserveEnergy) {
  auto md = make(square(20, 0.5, 8)); // 400 disks
  const auto n = static_cast<std::int64_t>(md.size());
  const double k0 = md.kinetic_energy();
  const Vec<2> p0 = md.momentum();
  for (int k = 0; k < 5; ++k) {
    md.run_collisions(10 * n);
    EXPECT_GE(md.min_relative_gap(), -1e-10);
  }
  EXPECT_NEAR(md.kinetic_energy() / k0, 1.0, 1e-10);
  EXPECT_LE((md.momentum() - p0).norm(), 1e-12 * momentum_scale(md));
  md.grow(0.65, 0.05);
  EXPECT_NEAR(md.solid_fraction(), 0.65, 1e-12);
  EXPECT_GE(md.min_relative_gap(), -1e-10);
  // 2D equation of state (Henderson): Z = (1 + eta^2/8) / (1 - eta)^2 = 6.80 at eta = 0.65
  // is not checked here (near the hexatic transition); a positive excess pressure is.
  md.run_collisions(20 * n);
  md.reset_pressure();
  md.run_collisions(20 * n);
  EXPECT_GT(compressibility(md), 2.0);
}

TEST(HardSphereMD, SmallBoxFallsBackToAllPairs) {
  // 32 spheres in a box of 3.2 diameters (3 cells per axis would fit): all pairs along every
  // axis, and a slab (few cells along z only). Both must conserve energy without overlap.
  for (int slab = 0; slab < 2; ++slab) {
    Config<3> c;
    std::mt19937_64 rng(9 + slab);
    const Vec<3> box = slab ? Vec<3>(9.0, 9.0, 2.6) : Vec<3>(3.2, 3.2, 3.2);
    c.box = box;
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const int n = slab ? 40 : 12;
    while (static_cast<int>(c.x.size()) < n) { // random sequential addition
      Vec<3> x(u(rng) * box[0], u(rng) * box[1], u(rng) * box[2]);
      bool ok = true;
      for (const auto& y : c.x) {
        Vec<3> d = x - y;
        for (int a = 0; a < 3; ++a)
          d[a] -= box[a] * std::round(d[a] / box[a]);
        ok = ok && d.norm() > 1.0;
      }
      if (ok)
        c.x.push_back(x);
    }
    c.r.assign(c.x.size(), 0.5);
    c.m.assign(c.x.size(), 1.0);
    thermalise(c, 11);
    auto md = make(c);
    const auto cells = md.cells_per_axis();
    EXPECT_EQ(cells[2], 1);
    if (slab)
      EXPECT_GE(cells[0], 4);
    else
      EXPECT_EQ(cells[0], 1);
    const double k0 = md.kinetic_energy();
    for (int k = 0; k < 10; ++k) {
      md.run_collisions(1000);
      EXPECT_GE(md.min_relative_gap(), -1e-10);
    }
    EXPECT_NEAR(md.kinetic_energy() / k0, 1.0, 1e-10);
  }
}

template <int dim> void head_on_collision() {
  // Two unit spheres at x = 2 and x = 5 approaching at +-1 (gap 2) collide at t = 1 at x = 3
  // and 4 and exchange velocities; with masses 1 and 3 the velocities become -2 and 0.
  Vec<dim> box = Vec<dim>::Constant(10.0);
  Vec<dim> x1 = Vec<dim>::Constant(5.0), x2 = x1, v1 = Vec<dim>::Zero(), v2 = v1;
  x1[0] = 2;
  x2[0] = 5;
  v1[0] = 1;
  v2[0] = -1;
  HardSphereMD<dim> md(box, {x1, x2}, {0.5, 0.5}, {1.0, 1.0}, {v1, v2});
  md.run_collisions(1);
  EXPECT_NEAR(md.time(), 1.0, 1e-14);
  EXPECT_NEAR(md.positions()[0][0], 3.0, 1e-14);
  EXPECT_NEAR(md.positions()[1][0], 4.0, 1e-14);
  EXPECT_NEAR(md.velocities()[0][0], -1.0, 1e-14);
  EXPECT_NEAR(md.velocities()[1][0], 1.0, 1e-14);
  EXPECT_NEAR(md.velocities()[0][1], 0.0, 1e-14);
  // They fly apart and meet again through the periodic boundary: the gap 10 - 1 - 1 = 8
  // closes at speed 2, at t = 1 + 4, with grain 0 at 3 - 4 = -1 (wrapped: 9) and grain 1 at 8.
  md.run_collisions(1);
  EXPECT_NEAR(md.time(), 5.0, 1e-12);
  EXPECT_NEAR(md.positions()[0][0], 9.0, 1e-12);
  EXPECT_NEAR(md.positions()[1][0], 8.0, 1e-12);
  EXPECT_EQ(md.collisions(), 2);

  HardSphereMD<dim> mm(box, {x1, x2}, {0.5, 0.5}, {1.0, 3.0}, {v1, v2});
  mm.run_collisions(1);
  EXPECT_NEAR(mm.velocities()[0][0], -2.0, 1e-14);
  EXPECT_NEAR(mm.velocities()[1][0], 0.0, 1e-14);
  // Pressure over [0, 1]: K = 2 throughout, one collision with r.dp = 1 * 3 (impulse
  // mu * 4, mu = 3/4): P = (2 K t + 3) / (dim V t), t = 1.
  EXPECT_NEAR(mm.pressure(), (2 * 2.0 + 1.0 * 3.0) / (dim * box.prod()), 1e-12);
}

TEST(HardSphereMD, TwoBodyHeadOnCollision3D) {
  head_on_collision<3>();
}
TEST(HardSphereMD, TwoBodyHeadOnCollision2D) {
  head_on_collision<2>();
}

TEST(HardSphereMD, GrowingPairCollidesWhenContactDistanceReachesSeparation) {
  // Two spheres of radius 0.5 at distance 2, moving together (no relative velocity): with
  // r(t) = 0.5 (1 + rate t) they touch at 1 + rate t = 2, t = 1/rate. Growing to a solid
  // fraction a bit beyond that must produce collisions and no overlap; just before, none.
  const double l = 10, rate = 0.5;
  Vec<3> box = Vec<3>::Constant(l), v = Vec<3>(0.0, 0.3, 0.0);
  const Vec<3> a(3, 5, 5), b(5, 5, 5);
  const double phi1 = 2 * std::numbers::pi / 6.0 / (l * l * l); // diameters 1
  {
    HardSphereMD<3> md(box, {a, b}, {0.5, 0.5}, {1.0, 1.0}, {v, v});
    md.grow(phi1 * std::pow(1.999, 3), rate);
    EXPECT_EQ(md.collisions(), 0);
    EXPECT_NEAR(md.min_relative_gap(), 2 / 1.999 - 1, 1e-12);
  }
  {
    HardSphereMD<3> md(box, {a, b}, {0.5, 0.5}, {1.0, 1.0}, {v, v});
    md.grow(phi1 * std::pow(2.0001, 3), rate);
    EXPECT_EQ(md.collisions(), 1);
    EXPECT_GE(md.min_relative_gap(), -1e-12);
    // LS rule: from v_n = 0 the pair leaves at v_n' = 2 sigma' (sigma' = (0.5 + 0.5) rate),
    // faster than the contact distance grows; the common y velocity is untouched.
    const Vec<3> dv = md.velocities()[1] - md.velocities()[0];
    EXPECT_NEAR(dv[0], 2 * rate, 1e-12);
    EXPECT_NEAR(md.velocities()[0][1], 0.3, 1e-14);
    // Contact at t = 1/rate = 2; the growth stops at g = 2.0001, t = 1.0001 / rate.
    EXPECT_NEAR(md.time(), 1.0001 / rate, 1e-12);
    EXPECT_NEAR(md.positions()[1][0] - md.positions()[0][0], 2 + 2 * rate * (1.0001 - 1.0) / rate,
                1e-12);
  }
}

TEST(HardSphereMD, RejectsOverlapButAcceptsTouching) {
  Vec<3> box = Vec<3>::Constant(10.0);
  const Vec<3> v1(1, 0, 0), v2(-1, 0, 0);
  EXPECT_THROW(HardSphereMD<3>(box, {Vec<3>(2, 5, 5), Vec<3>(2.999, 5, 5)}, {0.5, 0.5}, {1.0, 1.0},
                               {v1, v2}),
               Error);
  EXPECT_THROW(HardSphereMD<3>(Vec<3>::Constant(1.9), {Vec<3>(0, 0, 0)}, {0.5}, {1.0}, {v1}),
               Error);
  // Overlap of 1e-12 of the contact distance: an approaching pair collides at once.
  HardSphereMD<3> md(box, {Vec<3>(2, 5, 5), Vec<3>(3 - 1e-12, 5, 5)}, {0.5, 0.5}, {1.0, 1.0},
                     {v1, v2});
  md.run_collisions(1);
  EXPECT_EQ(md.time(), 0.0);
  EXPECT_NEAR(md.velocities()[0][0], -1.0, 1e-14);
}

TEST(HardSphereMD, ThroughputAt045) {
  // 4000 spheres at solid fraction 0.45 (the performance target is >= 1e6 collisions/s in
  // Release); reported, not asserted (machines differ), but the run must stay exact.
  auto md = make(fcc(10, 0.45, 12));
  const auto n = static_cast<std::int64_t>(md.size());
  md.run_collisions(20 * n);
  const double k0 = md.kinetic_energy();
  const std::int64_t runs = 250 * n;
  const auto start = std::chrono::steady_clock::now();
  md.run_collisions(runs);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("[          ] %lld collisions of %lld spheres in %.3f s: %.3g collisions/s\n",
              static_cast<long long>(runs), static_cast<long long>(n), s,
              static_cast<double>(runs) / s);
  EXPECT_NEAR(md.kinetic_energy() / k0, 1.0, 1e-10);
  EXPECT_GE(md.min_relative_gap(), -1e-10);
}

} // namespace
} // namespace granpack
