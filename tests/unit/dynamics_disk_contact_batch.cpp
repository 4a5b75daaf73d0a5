// The batched 2D contact kernel (DiskContactBatch) lane by lane against the scalar law it stands
// for (ContactLaw<2>::force) on single pairs placed to take each branch of the law: a cohesive
// contact at rest, one sliding, one rolling at its threshold, a pair across a gap within and
// beyond D0; the pairs off its path are flagged for the scalar law; the laws it must refuse are
// refused. The loop over a cloud of disks is tested in dynamics_contact_forces.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "granpack/contact/contact_law_params.h"
#include "granpack/dynamics/disk_contact_batch.h"

using namespace granpack;

namespace {

// [GRC]'s series A material in SI units per unit thickness (jobs/decks/2d/...).
constexpr double kRadius = 0.5e-3, kMass = 2500 * M_PI * kRadius * kRadius;
constexpr double kKn = 1e8, kF0 = 1.0, kD0 = 1e-6, kDt = 2e-8;

ContactLawParams grc_params() {
  ContactLawParams p;
  p.normal = NormalLawKind::kLinear;
  p.k_n = kKn;
  p.tangential = TangentialStiffnessKind::kRatio;
  p.k_t_ratio = 1.0;
  p.friction = 0.5;
  p.damping_ratio = 0.8;
  p.cohesion_force = kF0;
  p.cohesion_range = kD0;
  p.rolling_stiffness = 1e-2;
  p.rolling_friction = 5e-6;
  p.rolling_damping = 0.1;
  return p;
}

/// One pair: j at distance 2R - h along the direction `angle` from i, both kernels' inputs.
struct Pair {
  double h = 0, angle = 0.3;
  Vec<2> v = Vec<2>::Zero(); ///< v_j - v_i
  double w_i = 0, w_j = 0;
  ContactState<2> state;

  Vec<2> r() const { return (2 * kRadius - h) * Vec<2>(std::cos(angle), std::sin(angle)); }
};

void fill(DiskContactBatch& b, std::size_t l, const Pair& p) {
  const Vec<2> r = p.r();
  b.rx[l] = r[0];
  b.ry[l] = r[1];
  b.rad_i[l] = b.rad_j[l] = kRadius;
  b.mass_i[l] = b.mass_j[l] = kMass;
  b.vx[l] = p.v[0];
  b.vy[l] = p.v[1];
  b.wi[l] = p.w_i;
  b.wj[l] = p.w_j;
  b.tx[l] = p.state.tangential_force[0];
  b.ty[l] = p.state.tangential_force[1];
  b.n_old[l] = p.state.normal_force;
  b.rolling[l] = p.state.rolling[0];
}

/// Evaluates the pairs in one batch and checks every lane not flagged against the scalar law
/// (forces, torques, new history and flags to 1e-12 of their scale); returns the batch.
std::unique_ptr<DiskContactBatch> compare(const ContactLaw<2>& law, const std::vector<Pair>& pairs,
                                          DiskContactSums& sums) {
  auto b = std::make_unique<DiskContactBatch>();
  for (std::size_t l = 0; l < pairs.size(); ++l)
    fill(*b, l, pairs[l]);
  evaluate(*DiskContactConstants::of(law), *b, pairs.size(), kDt, sums);
  for (std::size_t l = 0; l < pairs.size(); ++l) {
    if (b->exact[l])
      continue;
    SCOPED_TRACE("lane " + std::to_string(l));
    Pair p = pairs[l];
    ContactKinematics<2> kin;
    kin.v_j = p.v;
    kin.w_i[0] = p.w_i;
    kin.w_j[0] = p.w_j;
    const auto g = make_pair_geometry<2>(kRadius, kRadius, kMass, kMass, p.r());
    const ContactForces<2> f = law.force(g, kin, p.state, kDt);
    EXPECT_TRUE(f.active);
    // The scale of the terms summed; h = 2R - |r| carries a few ulps of |r| (cancellation).
    const double eps = std::numeric_limits<double>::epsilon();
    const double rel = 1e-12 + 8 * eps * g.distance / std::abs(g.overlap);
    const double scale =
        std::abs(f.normal_elastic) + std::abs(f.normal_total) + kF0 + f.tangential.norm();
    EXPECT_NEAR(b->fx[l], f.force_on_j[0], rel * scale);
    EXPECT_NEAR(b->fy[l], f.force_on_j[1], rel * scale);
    const double moment_scale = rel * (scale * kRadius + 1e-2 * std::abs(p.state.rolling[0]));
    EXPECT_NEAR(b->ti[l], f.torque_i[0], moment_scale);
    EXPECT_NEAR(b->tj[l], f.torque_j[0], moment_scale);
    EXPECT_NEAR(b->tx[l], p.state.tangential_force[0], rel * scale);
    EXPECT_NEAR(b->ty[l], p.state.tangential_force[1], rel * scale);
    EXPECT_NEAR(b->n_old[l], p.state.normal_force, rel * scale);
    EXPECT_NEAR(b->rolling[l], p.state.rolling[0], 1e-12 * std::abs(p.state.rolling[0]));
    EXPECT_EQ(static_cast<std::uint32_t>(b->flags[l]), p.state.flags);
  }
  return b;
}

} // namespace

TEST(DiskContactBatch, MatchesTheScalarLawOnEachBranch) {
  const ContactLaw<2> law = make_contact_law<2>(grc_params());
  const double h0 = kF0 / kKn; // isolated equilibrium deflection ([GRC] eq. 11)
  std::vector<Pair> pairs(7);
  // 0: cohesive contact at rest at h0 with a history inside both thresholds.
  pairs[0].h = h0;
  pairs[0].state.normal_force = kKn * h0;
  pairs[0].state.tangential_force = 0.1 * Vec<2>(-std::sin(0.3), std::cos(0.3));
  pairs[0].state.rolling[0] = 1e-5;
  pairs[0].state.age = 100;
  // 1: sliding (T beyond μ N^e after the increment), moving at 0.1 m/s.
  pairs[1] = pairs[0];
  pairs[1].v = Vec<2>(1.0, -0.5) * 1e-1;
  pairs[1].state.tangential_force *= 5.0;
  // 2: rolling beyond μ_r N^e (K_r δθ = 1e-2 x 1e-3 > 5e-6 x 1), spinning.
  pairs[2] = pairs[0];
  pairs[2].state.rolling[0] = 1e-3;
  pairs[2].w_i = -30.0;
  pairs[2].w_j = 50.0;
  // 3: a new contact, closing.
  pairs[3].h = 0.3 * h0;
  pairs[3].v = -1e-2 * pairs[3].r().normalized();
  // 4: across a gap of D0 / 3: attraction only, every history forgotten.
  pairs[4] = pairs[2];
  pairs[4].h = -kD0 / 3;
  // 5: across a gap beyond D0 (the loop's range test lets it through when rounding differs):
  // off the path. 6: a contact turning by 1e-2 rad in the step, with a T to transport: off the
  // path (the scalar law's cos and sin).
  pairs[5].h = -2 * kD0;
  pairs[6] = pairs[0];
  pairs[6].v = 1e-2 / kDt * 2 * kRadius * Vec<2>(-std::sin(0.3), std::cos(0.3));
  DiskContactSums sums;
  const auto b = compare(law, pairs, sums);
  for (int l = 0; l < 5; ++l)
    EXPECT_EQ(b->exact[l], 0) << l;
  EXPECT_EQ(b->exact[5], 1);
  EXPECT_EQ(b->exact[6], 1);
  EXPECT_EQ(sums.contacts, 5);
  EXPECT_EQ(b->flags[1], static_cast<int>(kSliding));
  EXPECT_EQ(b->flags[2], static_cast<int>(kRollingPlastic));
  EXPECT_EQ(b->flags[4], static_cast<int>(kDistant));
  EXPECT_NEAR(b->fx[4], -(2.0 / 3.0) * kF0 * std::cos(0.3), 1e-12);
  EXPECT_EQ(b->ti[4], 0.0);
  EXPECT_EQ(b->rolling[4], 0.0);
}

TEST(DiskContactBatch, EvaluatesTheLawsWithoutCohesionOrRollingAndRefusesAConstantKt) {
  auto plain = grc_params();
  plain.cohesion_force = plain.cohesion_range = 0;
  plain.rolling_stiffness = plain.rolling_friction = plain.rolling_damping = 0;
  const ContactLaw<2> law = make_contact_law<2>(plain);
  ASSERT_TRUE(DiskContactConstants::of(law).has_value());
  std::vector<Pair> pairs(3);
  pairs[0].h = 1e-8;
  pairs[0].w_j = 20.0;
  pairs[0].v = Vec<2>(0.01, 0.02);
  pairs[1] = pairs[0];
  pairs[1].state.normal_force = 1.0;
  pairs[1].state.tangential_force = 0.3 * Vec<2>(-std::sin(0.3), std::cos(0.3));
  pairs[2].h = -1e-9; // apart, no cohesion: off the path (not interacting)
  DiskContactSums sums;
  const auto b = compare(law, pairs, sums);
  EXPECT_EQ(b->exact[0], 0);
  EXPECT_EQ(b->exact[1], 0);
  EXPECT_EQ(b->exact[2], 1);
  EXPECT_EQ(b->rolling[0], 0.0); // no rolling resistance: δθ stays 0

  auto constant = plain;
  constant.tangential = TangentialStiffnessKind::kConstant;
  constant.k_t = 1e7;
  EXPECT_FALSE(DiskContactConstants::of(make_contact_law<2>(constant)).has_value());
}
