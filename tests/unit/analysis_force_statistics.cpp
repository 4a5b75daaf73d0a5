#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "granpack/analysis/force_statistics.h"

using namespace granpack;

namespace {

constexpr double kPi = std::numbers::pi;

/// The hand-made list: N = 1, 2, 3, 6 (<N> = 3), |T| = 0.1, 0.6, 0.3, 1.2, deflections
/// 0.01 ... 0.04; contact 1 touches a divalent grain, contacts 2 and 3 a trivalent one, and
/// contact 3 (N = 6) both.
std::vector<ContactForceSample> hand_made() {
  return {{1.0, 0.1, 0.01, 5, 6},
          {2.0, 0.6, 0.02, 2, 4},
          {3.0, 0.3, 0.03, 3, 5},
          {6.0, 1.2, 0.04, 2, 3}};
}

/// Both passes over `contacts`, as one rank would (the driver reduces in between).
struct TwoPasses {
  ForceMomentSums p1;
  ForceSplitSums p2;
};
TwoPasses run(const std::vector<ContactForceSample>& contacts, std::vector<double> alphas) {
  ForceMomentSums p1(std::move(alphas));
  p1.add(contacts);
  ForceSplitSums p2(p1.mean_normal_force());
  p2.add(contacts);
  return {p1, p2};
}

} // namespace

TEST(ForceStatistics, MomentsAndStrongWeakSplitByHand) {
  const auto c = hand_made();
  auto [p1, p2] = run(c, {1.0, 5.0 / 3.0, 2.0, 3.0});
  EXPECT_DOUBLE_EQ(p1.mean_normal_force(), 3.0);
  PackingScales sc{.pressure = 2.0,
                   .diameter = 0.5,
                   .solid_fraction = 0.6,
                   .n_grains = 4,
                   .volume = 10.0,
                   .e_tilde = 0};
  const auto r = finish_force_statistics<3>(p1, p2, sc);

  EXPECT_DOUBLE_EQ(r.contacts, 4);
  EXPECT_DOUBLE_EQ(r.coordination, 2.0); // 2 * 4 contacts / 4 grains
  ASSERT_EQ(r.moments.size(), 4u);
  EXPECT_NEAR(r.moments[0], 1.0, 1e-15);
  const double z53 =
      (1 + std::pow(2.0, 5.0 / 3) + std::pow(3.0, 5.0 / 3) + std::pow(6.0, 5.0 / 3)) / 4 /
      std::pow(3.0, 5.0 / 3);
  EXPECT_NEAR(r.moments[1], z53, 1e-14);
  EXPECT_NEAR(r.z_5_3, z53, 1e-14);
  EXPECT_NEAR(r.moments[2], (1 + 4 + 9 + 36) / 4.0 / 9.0, 1e-14);    // 25/18
  EXPECT_NEAR(r.moments[3], (1 + 8 + 27 + 216) / 4.0 / 27.0, 1e-14); // 7/3

  // All contacts: only N = 6 exceeds <N> = 3 (N = 3 is weak).
  EXPECT_DOUBLE_EQ(r.all.contacts, 4);
  EXPECT_DOUBLE_EQ(r.all.strong_fraction, 0.25);
  EXPECT_NEAR(r.all.strong_mobilization, 1.2 / 6, 1e-15);
  EXPECT_NEAR(r.all.weak_mobilization, (0.1 / 1 + 0.6 / 2 + 0.3 / 3) / 3, 1e-15);
  EXPECT_NEAR(r.all.mean_normal_force, 3.0 / (2.0 * 0.25), 1e-15); // <N> / (P a^2)
  // Divalent population: contacts 1 (N = 2, weak) and 3 (N = 6, strong).
  EXPECT_DOUBLE_EQ(r.divalent.contacts, 2);
  EXPECT_DOUBLE_EQ(r.divalent.strong_fraction, 0.5);
  EXPECT_NEAR(r.divalent.strong_mobilization, 0.2, 1e-15);
  EXPECT_NEAR(r.divalent.weak_mobilization, 0.3, 1e-15);
  EXPECT_NEAR(r.divalent.mean_normal_force, 4.0 / 0.5, 1e-14);
  // Trivalent population: contacts 2 (N = 3, weak) and 3 (N = 6, strong).
  EXPECT_DOUBLE_EQ(r.trivalent.contacts, 2);
  EXPECT_DOUBLE_EQ(r.trivalent.strong_fraction, 0.5);
  EXPECT_NEAR(r.trivalent.strong_mobilization, 0.2, 1e-15);
  EXPECT_NEAR(r.trivalent.weak_mobilization, 0.1, 1e-15);
  EXPECT_NEAR(r.trivalent.mean_normal_force, 4.5 / 0.5, 1e-14);

  // P(f): f = 1/3, 2/3, 1, 2 in bins of width 0.1 -> bins 3, 6, 10, 20, density 1/(4 * 0.1).
  ASSERT_EQ(r.pdf.size(), 50u);
  ASSERT_EQ(r.f_edges.size(), 51u);
  for (std::size_t k = 0; k < 50; ++k) {
    const bool hit = k == 3 || k == 6 || k == 10 || k == 20;
    EXPECT_NEAR(r.pdf[k], hit ? 2.5 : 0.0, 1e-12) << "bin " << k;
  }
  EXPECT_EQ(r.fraction_above, 0);
  EXPECT_EQ(r.fraction_below, 0);
  // No Hertz modulus: eq. (28) is not defined.
  EXPECT_TRUE(std::isnan(r.kappa));
  EXPECT_TRUE(std::isnan(r.delta_phi_eq28));
  // eq. (26): Phi sum N h / (Omega P) = 0.6 * (0.01 + 0.04 + 0.09 + 0.24) / 20.
  EXPECT_NEAR(r.delta_phi_eq26, 0.6 * 0.38 / 20, 1e-15);
}

TEST(ForceStatistics, EmptyPopulationsAreNaNAndOverflowCounts) {
  // No 2- or 3-coordinated grain; one force beyond f_max and one negative (cohesion).
  std::vector<ContactForceSample> c = {
      {1, 0, 0, 4, 4}, {1, 0, 0, 5, 5}, {13, 0, 0, 6, 6}, {-1, 0, 0, 4, 5}};
  ForceMomentSums p1({2.0});
  p1.add(c);
  EXPECT_DOUBLE_EQ(p1.mean_normal_force(), 3.5);
  ForceSplitSums p2(p1.mean_normal_force(), ForceBins{.f_max = 2.0, .bins = 20});
  p2.add(c);
  const auto r = finish_force_statistics<3>(p1, p2, {1, 1, 0.6, 8, 1, 0});
  EXPECT_DOUBLE_EQ(r.fraction_above, 0.25); // f = 13 / 3.5 >= 2
  EXPECT_DOUBLE_EQ(r.fraction_below, 0.25); // f = -1 / 3.5
  EXPECT_NEAR(r.pdf[2], 0.5 / 0.1, 1e-12);  // f = 1 / 3.5 = 0.286 (twice)
  EXPECT_TRUE(std::isnan(r.divalent.strong_fraction));
  EXPECT_TRUE(std::isnan(r.trivalent.weak_mobilization));
  EXPECT_DOUBLE_EQ(r.all.strong_fraction, 0.25);
}

TEST(ForceStatistics, SplittingContactsAmongRanksGivesTheSameSums) {
  std::vector<ContactForceSample> c;
  for (int k = 0; k < 101; ++k)
    c.push_back({0.1 + std::fmod(0.37 * k, 2.9), 0.05 * std::fmod(0.11 * k, 1.0), 1e-3 * k,
                 2 + k % 5, 3 + k % 7});
  auto whole = run(c, {5.0 / 3.0, 2.0});
  // Rank 0 gets the even contacts, rank 1 the odd ones; pass 1, reduce, pass 2, reduce.
  std::vector<ContactForceSample> even, odd;
  for (std::size_t k = 0; k < c.size(); ++k)
    (k % 2 ? odd : even).push_back(c[k]);
  ForceMomentSums a({5.0 / 3.0, 2.0}), b({5.0 / 3.0, 2.0});
  a.add(even);
  b.add(odd);
  a.merge(b);
  ForceSplitSums sa(a.mean_normal_force()), sb(a.mean_normal_force());
  sa.add(even);
  sb.add(odd);
  sa.merge(sb);
  for (std::size_t k = 0; k < a.sums().size(); ++k)
    EXPECT_NEAR(a.sums()[k], whole.p1.sums()[k], 1e-12 * std::abs(whole.p1.sums()[k]));
  ASSERT_EQ(sa.sums().size(), whole.p2.sums().size());
  for (std::size_t k = 0; k < sa.sums().size(); ++k)
    EXPECT_NEAR(sa.sums()[k], whole.p2.sums()[k], 1e-12 * std::abs(whole.p2.sums()[k]));
}

namespace {

/// A consistent set of Hertz contacts: n grains of diameter a at solid fraction phi, N_c
/// contacts with deflections h and N = Ẽ sqrt(a) h^{3/2} / 3, and P = sum N a / (dim Omega):
/// the stress of eq. (16) with every branch vector of length a, the assumption of eq. (22).
template <int dim> struct Consistent {
  std::vector<ContactForceSample> contacts;
  PackingScales scales;
};
template <int dim> Consistent<dim> consistent_case() {
  Consistent<dim> cs;
  const double a = 2e-3, e_tilde = 7.7e10, phi = 0.62;
  const int n = 40;
  double sum_n = 0;
  for (int k = 0; k < 97; ++k) {
    const double h = a * 1e-5 * (0.2 + std::fmod(0.618 * k, 1.7));
    const double nf = e_tilde * std::sqrt(a) * std::pow(h, 1.5) / 3;
    cs.contacts.push_back({nf, 0.1 * nf, h, 4, 5});
    sum_n += nf;
  }
  const double grain = dim == 3 ? kPi * a * a * a / 6 : kPi * a * a / 4;
  const double volume = n * grain / phi;
  cs.scales = {sum_n * a / (dim * volume), a, phi, double(n), volume, e_tilde};
  return cs;
}

template <int dim> void check_consistent_case() {
  const auto cs = consistent_case<dim>();
  auto [p1, p2] = run(cs.contacts, {2.0});
  const auto r = finish_force_statistics<dim>(p1, p2, cs.scales);
  EXPECT_NEAR(r.eq22_ratio, 1.0, 1e-12);
  EXPECT_NEAR(r.pressure_eq22, cs.scales.pressure, 1e-12 * cs.scales.pressure);
  // eq. (28) is eq. (26) with the Hertz law and eq. (22): exact here.
  EXPECT_GT(r.delta_phi_eq26, 0);
  EXPECT_NEAR(r.delta_phi_eq28, r.delta_phi_eq26, 1e-10 * r.delta_phi_eq26);
  EXPECT_NEAR(r.phi0_eq28, cs.scales.solid_fraction - r.delta_phi_eq28, 1e-15);
  // A pressure 10 % off eq. (22) shows in the ratio.
  auto off = cs.scales;
  off.pressure *= 1.1;
  EXPECT_NEAR(finish_force_statistics<dim>(p1, p2, off).eq22_ratio, 1 / 1.1, 1e-12);
}

} // namespace

TEST(ForceStatistics, Eq22RatioIsOneAndEq28MatchesEq26OnAConsistentCase3D) {
  check_consistent_case<3>();
}
TEST(ForceStatistics, Eq22RatioIsOneAndEq28MatchesEq26OnAConsistentCase2D) {
  check_consistent_case<2>();
}

TEST(ForceStatistics, Eq28ReproducesThePaperNumber) {
  // [AR] sec. III B: Z(5/3) = 1.284, z = 5.995, Phi = 0.637, kappa = 39000 -> 1.15e-4.
  EXPECT_NEAR(delta_phi_eq28<3>(0.637, 5.995, 1.284, 39000), 1.15e-4, 0.005e-4);
}

TEST(Hyperstaticity, SimpleCounts) {
  // Frictionless 3D: H = N_c - 3 n*. Isostatic z* = 6: 30 contacts on 10 grains.
  auto h = hyperstaticity<3>(30, 10, 0, false);
  EXPECT_DOUBLE_EQ(h.degree, 0);
  EXPECT_DOUBLE_EQ(h.dof, 30);
  EXPECT_DOUBLE_EQ(h.z_star, 6);
  EXPECT_DOUBLE_EQ(h.z0_star, 6);
  h = hyperstaticity<3>(36, 10, 3, false); // divalent count ignored without friction
  EXPECT_DOUBLE_EQ(h.degree, 6);
  EXPECT_DOUBLE_EQ(h.per_dof, 0.2);
  // Frictional 3D: H = 3 N_c + n2 - 6 n*. 20 contacts, 10 grains, 2 divalent: 60 + 2 - 60.
  h = hyperstaticity<3>(20, 10, 2, true);
  EXPECT_DOUBLE_EQ(h.degree, 2);
  EXPECT_DOUBLE_EQ(h.dof, 60);
  EXPECT_DOUBLE_EQ(h.per_dof, 2.0 / 60);
  EXPECT_DOUBLE_EQ(h.z_star, 4);
  EXPECT_NEAR(h.z0_star, 4 - 2.0 * 2 / 30, 1e-15);          // 4 - 2 x2 / (3 (1 - x0))
  EXPECT_NEAR(h.z_star_corrected, 4 + 2.0 * 2 / 30, 1e-15); // z**
  EXPECT_NEAR(h.per_dof, (h.z_star_corrected - 4) / 4, 1e-15);
  // 2D: frictional H = 2 N_c - 3 n* (no divalent mechanism), frictionless H = N_c - 2 n*.
  h = hyperstaticity<2>(16, 10, 2, true);
  EXPECT_DOUBLE_EQ(h.degree, 2);
  EXPECT_DOUBLE_EQ(h.dof, 30);
  EXPECT_DOUBLE_EQ(h.z0_star, 3);
  h = hyperstaticity<2>(21, 10, 0, false);
  EXPECT_DOUBLE_EQ(h.degree, 1);
  EXPECT_DOUBLE_EQ(h.z0_star, 4);
}

TEST(Hyperstaticity, ReproducesThePaperValues) {
  // [AR] sec. IV D-F: H/N_f = 0.141 (D), 0.145 (C), 0.031 (Z) from z*, x0, x2 (tables IV, V).
  struct State {
    double z_star, x0, x2, expected;
  };
  for (const auto& s : {State{4.546, 0.111, 0.0239, 0.141}, State{4.56, 0.133, 0.0264, 0.145},
                        State{4.068, 0.184, 0.068, 0.031}}) {
    const double n = 1e6; // grains, rattlers included
    const auto nb = std::llround(n * (1 - s.x0));
    const auto h = hyperstaticity<3>(std::llround(s.z_star * double(nb) / 2), nb,
                                     std::llround(n * s.x2), true);
    EXPECT_NEAR(h.per_dof, s.expected, 0.0006) << "z* " << s.z_star;
  }
}
