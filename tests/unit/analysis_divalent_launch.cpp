// The launch of a divalent grain ([AR] App. E, analysis/divalent_launch.h): the frame and D
// of App. E, E1 exactly and E2 to O(h/a), the launch velocity field as the null vector of the
// stiffness (|K(1) x| at round-off, x the grain's (v, ell Omega) with the neighbours at rest),
// omega0 from the centrifugal ratio, and the ranking of the candidates.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "granpack/analysis/divalent_launch.h"
#include "granpack/analysis/rigidity_blocks.h"
#include "granpack/contact/contact_law_params.h"
#include "granpack/core/error.h"

using namespace granpack;

namespace {

constexpr double kRadius = 0.5e-3;

/// A divalent grain at the origin touching j and k (equal spheres), contacts nearly opposite
/// (the force line within the friction cone), overlaps h_j and h_k.
struct Grain {
  Vec<3> r_ij, r_ik;
  PairGeometry<3> gj, gk;
  Grain(double h_j = 2e-6, double h_k = 1e-6) {
    r_ij = Vec<3>(0.2, 0.95, 0.1).normalized() * (2 * kRadius - h_j);
    r_ik = Vec<3>(-0.25, -0.9, 0.05).normalized() * (2 * kRadius - h_k);
    gj = make_pair_geometry<3>(kRadius, kRadius, 1, 1, r_ij);
    gk = make_pair_geometry<3>(kRadius, kRadius, 1, 1, r_ik);
  }
  DivalentLaunch launch(double omega0) const {
    return divalent_launch(r_ij, r_ik, gj.branch_i(), gk.branch_i(), omega0);
  }
};

} // namespace

TEST(DivalentLaunch, FrameAndDistanceAreAppendixE) {
  const Grain g;
  const DivalentFrame fr = divalent_frame(g.r_ij, g.r_ik);
  const Vec<3> n_ij = g.r_ij.normalized(), n_ik = g.r_ik.normalized();
  EXPECT_NEAR(fr.e.dot((n_ik - n_ij).normalized()), 1.0, 1e-14);
  EXPECT_NEAR(fr.t.dot(n_ij), 0.0, 1e-14);
  EXPECT_NEAR(fr.t.dot(n_ik), 0.0, 1e-14);
  EXPECT_NEAR(fr.f.dot(fr.t.cross(fr.e)), 1.0, 1e-14);
  // [AR]: D = a sqrt(1 - (e.n_ij)^2) for equal spheres with a the centre distance. With
  // overlaps of 2e-6 and 1e-6 m the lines of the centres and of the normals differ by
  // O(h / D) ~ 1e-3 relative (D ~ 0.17 a here): both forms agree to that.
  const double d_ar = g.r_ij.norm() * std::sqrt(1 - std::pow(fr.e.dot(n_ij), 2));
  EXPECT_NEAR(fr.distance, d_ar, 1e-3 * fr.distance);
  EXPECT_GT(fr.distance, 0.1 * kRadius);
  // The grain's centre lies at +D f from the j-k line: fig. 16's trajectories start at (D, 0).
  EXPECT_NEAR((-g.r_ij).dot(fr.f), fr.distance, 1e-3 * fr.distance);
  EXPECT_NEAR((-g.r_ik).dot(fr.f), fr.distance, 1e-3 * fr.distance);
  // Equal overlaps: [AR]'s formula exactly.
  const Grain same(1e-6, 1e-6);
  const DivalentFrame fs = divalent_frame(same.r_ij, same.r_ik);
  EXPECT_NEAR(fs.distance,
              same.r_ij.norm() * std::sqrt(1 - std::pow(fs.e.dot(same.r_ij.normalized()), 2)),
              1e-12 * kRadius);
  EXPECT_NEAR((-same.r_ij).dot(fs.f), fs.distance, 1e-12 * kRadius);
}

TEST(DivalentLaunch, VelocitiesAreE1E2AndMoveNeitherContactPoint) {
  const Grain g;
  const double omega0 = 12.5;
  const DivalentLaunch l = g.launch(omega0);
  // E1 exactly.
  EXPECT_LT((l.velocity - omega0 * l.frame.distance * l.frame.t).norm(), 1e-14 * omega0 * kRadius);
  // E2: Omega = 2 omega0 e up to the overlaps (h / a ~ 1e-3 here).
  EXPECT_LT((l.angular_velocity - 2 * omega0 * l.frame.e).norm(), 5e-3 * 2 * omega0);
  // Rolling without sliding at both contact points (neighbours at rest).
  for (const Vec<3>& b : {g.gj.branch_i(), g.gk.branch_i()})
    EXPECT_LT((l.velocity + l.angular_velocity.cross(b)).norm(), 1e-13 * omega0 * kRadius);
}

TEST(DivalentLaunch, LaunchIsTheStiffnessNullVector) {
  // |K(1) x| / (k_n |x|) at round-off for the grain's launch (v, ell Omega), neighbours at rest:
  // the mode `granpack stiffness` removes as divalent, and parallel to divalent_rolling_mode.
  const Grain g;
  ContactLawParams prm;
  prm.young_modulus = 70e9;
  prm.poisson_ratio = 0.3;
  prm.friction = 0.3;
  const ContactLaw<3> law = make_contact_law<3>(prm);
  RigidityLayout<3> layout;
  layout.ell = kRadius;
  const DivalentLaunch l = g.launch(10.0);
  DynVector x = DynVector::Zero(layout.local_size());
  x.head<3>() = l.velocity;
  x.segment<3>(3) = layout.ell * l.angular_velocity;
  double k_n = 0, residual = 0;
  for (const PairGeometry<3>& geom : {g.gj, g.gk}) {
    RigidityContact<3> c;
    c.geometry = geom;
    c.normal_force = 1e-3;
    c.stiffness = law.stiffness(geom, ContactState<3>{});
    k_n = std::max(k_n, c.stiffness.k_n);
    residual += (constitutive_block(c, layout) * x).norm();
    EXPECT_LT((rigidity_rows(c, layout) * x).norm(), 1e-13 * x.norm());
  }
  EXPECT_GT(k_n, 0);
  EXPECT_LT(residual / (k_n * x.norm()), 1e-12);
  // A plain translation at the same speed is no mechanism: the test can fail.
  DynVector y = DynVector::Zero(layout.local_size());
  y.head<3>() = l.velocity;
  RigidityContact<3> c;
  c.geometry = g.gj;
  c.stiffness = law.stiffness(g.gj, ContactState<3>{});
  EXPECT_GT((constitutive_block(c, layout) * y).norm() / (k_n * y.norm()), 1e-3);
  const auto mode = divalent_rolling_mode(g.gj.branch_i(), g.gk.branch_i(), layout.ell);
  EXPECT_NEAR(std::abs(mode.dot(x.head<6>().normalized())), 1.0, 1e-12);
}

TEST(DivalentLaunch, Omega0GivesTheCentrifugalRatio) {
  const double m = 1.309e-6, d = 1.7e-4, f = 2.3e-3;
  for (double ratio : {1e-4, 1e-2}) {
    const double w = divalent_omega0(m, d, f, ratio);
    EXPECT_NEAR(m * w * w * d / f, ratio, 1e-12 * ratio);
  }
  EXPECT_THROW(divalent_omega0(m, 0.0, f, 1e-4), Error);
  EXPECT_THROW(divalent_omega0(m, d, 0.0, 1e-4), Error);
}

TEST(DivalentLaunch, AlignedCentresAreRefused) {
  EXPECT_THROW(divalent_frame(Vec<3>(1e-3, 0, 0), Vec<3>(-1e-3, 0, 0)), Error);
}

TEST(DivalentLaunch, CandidatesRankedByForce) {
  const auto rec = [](GlobalId grain, GlobalId nb, double force) {
    DivalentContactRecord r;
    r.grain = grain, r.neighbour = nb, r.force = force;
    return r;
  };
  // Grain 7: forces 3 and 3.1 (ranked by 3); grain 2: 5 and 4.9; grain 9: 1 and 1.
  const auto c = divalent_candidates({rec(7, 40, 3.1), rec(2, 11, 5.0), rec(9, 1, 1.0),
                                      rec(7, 3, 3.0), rec(2, 5, 4.9), rec(9, 2, 1.0)});
  ASSERT_EQ(c.size(), 3u);
  EXPECT_EQ(c[0].grain, 2);
  EXPECT_EQ(c[1].grain, 7);
  EXPECT_EQ(c[2].grain, 9);
  EXPECT_EQ(c[1].contact[0].neighbour, 3); // neighbour ids ascending: j < k
  EXPECT_EQ(c[1].contact[1].neighbour, 40);
  EXPECT_DOUBLE_EQ(c[0].force(), 4.9);
  EXPECT_THROW(divalent_candidates({rec(7, 40, 3.1), rec(7, 3, 3.0), rec(7, 5, 1.0)}), Error);
}
