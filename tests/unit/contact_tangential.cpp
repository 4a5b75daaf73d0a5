// Contact law, tangential part: Coulomb projection, Walton rescaling (energy over a cycle),
// objectivity under rigid rotation of the pair (docs/contact-law.md).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <limits>

#include "granpack/contact/contact_law.h"
#include "granpack/contact/contact_law_params.h"

using namespace granpack;

namespace {

constexpr double kE = 70e9, kNu = 0.3;
constexpr double kR = 0.5e-3, kMass = 1.3e-6; // glass sphere, d = 1 mm
const double kInf = std::numeric_limits<double>::infinity();

template <int dim> ContactLaw<dim> hertz_law(double mu, bool walton = true) {
  ContactLawParams p;
  p.young_modulus = kE;
  p.poisson_ratio = kNu;
  p.friction = mu;
  p.walton_rescaling = walton;
  return make_contact_law<dim>(p);
}

template <int dim> RotVec<dim> spin_about_z(double w) {
  RotVec<dim> r = RotVec<dim>::Zero();
  r[rot_dim<dim> - 1] = w; // z component in 3D, the only one in 2D
  return r;
}

/// Grain i fixed at the origin, j on the x axis; j may translate along x and spin about z
/// (which slides its contact point along y). Tracks the work done on the contact.
template <int dim> struct SpinRig {
  ContactLaw<dim> law;
  ContactState<dim> state;
  Vec<dim> x_j = Vec<dim>::Zero();
  ContactForces<dim> last;
  double work = 0; // work done ON the contact by the agent holding j (trapezoid rule)

  SpinRig(const ContactLaw<dim>& l, double h) : law(l) {
    x_j[0] = 2 * kR - h;
    last = evaluate(ContactKinematics<dim>{}, 1.0);
  }
  ContactForces<dim> evaluate(const ContactKinematics<dim>& kin, double dt) {
    return law.force(make_pair_geometry<dim>(kR, kR, kMass, kMass, x_j), kin, state, dt);
  }
  /// One quasi-static step (dt = 1): move j by dx along x and turn it by dphi about z.
  void step(double dx, double dphi) {
    ContactKinematics<dim> kin;
    kin.v_j[0] = dx;
    kin.w_j = spin_about_z<dim>(dphi);
    x_j[0] += dx;
    const ContactForces<dim> f = evaluate(kin, 1.0);
    const Vec<dim> favg = 0.5 * (f.force_on_j + last.force_on_j);
    const RotVec<dim> tavg = 0.5 * (f.torque_j + last.torque_j);
    work -= favg[0] * dx + tavg[rot_dim<dim> - 1] * dphi;
    last = f;
  }
};

template <typename T> class ContactTangentialTest : public ::testing::Test {};
template <int d> struct Dim { static constexpr int value = d; };
using Dims = ::testing::Types<Dim<2>, Dim<3>>;
TYPED_TEST_SUITE(ContactTangentialTest, Dims);

} // namespace

TYPED_TEST(ContactTangentialTest, CoulombSaturatesAtMuTimesElasticNormalForce) {
  constexpr int dim = TypeParam::value;
  const double h = 2e-6, mu = 0.3, dphi = 5e-6; // contact point moves ~2.5e-9 m per step
  SpinRig<dim> rig(hertz_law<dim>(mu), h);
  const double n_e = rig.last.normal_elastic;
  const double k_t =
      rig.law.stiffness(make_pair_geometry<dim>(kR, kR, kMass, kMass, rig.x_j), rig.state).k_t;
  const double arm = kR - h / 2;
  bool saw_elastic = false;
  for (int s = 1; s <= 400; ++s) {
    rig.step(0.0, dphi);
    const double t = rig.last.tangential.norm();
    const double elastic = k_t * arm * dphi * s;
    if (elastic < mu * n_e * (1 - 1e-9)) {
      EXPECT_NEAR(t / elastic, 1.0, 1e-9) << "step " << s;
      EXPECT_FALSE(rig.state.flags & kSliding);
      saw_elastic = true;
    } else if (elastic > mu * n_e * (1 + 1e-9)) {
      EXPECT_NEAR(t / (mu * n_e), 1.0, 1e-14) << "step " << s;
      EXPECT_TRUE(rig.state.flags & kSliding);
    }
    EXPECT_LE(t, mu * n_e * (1 + 1e-14));
  }
  EXPECT_TRUE(saw_elastic);
  EXPECT_TRUE(rig.state.flags & kSliding);
  // Friction on j opposes the motion of its contact point (ω_z > 0 at -x branch moves -y).
  EXPECT_GT(rig.last.tangential[1], 0.0);
  // Reversing the motion leaves the cone at once.
  rig.step(0.0, -dphi);
  EXPECT_FALSE(rig.state.flags & kSliding);
  EXPECT_LT(rig.last.tangential.norm(), mu * n_e);
}

TYPED_TEST(ContactTangentialTest, ZeroFrictionGivesNoTangentialForce) {
  constexpr int dim = TypeParam::value;
  SpinRig<dim> rig(hertz_law<dim>(0.0), 2e-6);
  for (int s = 0; s < 50; ++s) {
    rig.step(0.0, 1e-5);
    EXPECT_EQ(rig.last.tangential.norm(), 0.0);
    EXPECT_EQ(rig.last.torque_j.norm(), 0.0);
  }
}

TYPED_TEST(ContactTangentialTest, InfiniteFrictionNeverSlides) {
  constexpr int dim = TypeParam::value;
  const double h = 2e-6, dphi = 1e-4;
  SpinRig<dim> rig(hertz_law<dim>(kInf), h);
  const double k_t =
      rig.law.stiffness(make_pair_geometry<dim>(kR, kR, kMass, kMass, rig.x_j), rig.state).k_t;
  const int steps = 500;
  for (int s = 0; s < steps; ++s)
    rig.step(0.0, dphi);
  EXPECT_FALSE(rig.state.flags & kSliding);
  const double t = rig.last.tangential.norm();
  EXPECT_NEAR(t / (k_t * (kR - h / 2) * dphi * steps), 1.0, 1e-9);
  EXPECT_GT(t, 10 * rig.last.normal_elastic); // far beyond any Coulomb limit used here
}

// Cycle: (1) h0 -> h1 at fixed tangential displacement (T = 0), (2) slide the contact point
// at h1, (3) h1 -> h0 at fixed tangential displacement, (4) slide back at h0. Positions and
// orientations return to the start. Hertz-Mindlin, μ = inf (always elastic).
// With Walton's rule step (3) scales T by K_T(h0)/K_T(h1): the work done on the contact is
// ½ (K_T1 - K_T0) u² >= 0. Without it T is unchanged in (3), and the work is
// ½ (K_T0 - K_T1) u² < 0 while the contact even ends with T != 0 (more stored energy):
// energy is created, which is why [AR] App. A rescales T.
TYPED_TEST(ContactTangentialTest, WaltonRescalingMakesLoadUnloadCycleDissipative) {
  constexpr int dim = TypeParam::value;
  const double h0 = 1e-6, h1 = 3e-6, phi = 4e-4;
  const int steps = 200;
  double work[2] = {0, 0};
  for (int walton = 0; walton < 2; ++walton) {
    SpinRig<dim> rig(hertz_law<dim>(kInf, walton == 1), h0);
    for (int s = 0; s < steps; ++s)
      rig.step(-(h1 - h0) / steps, 0.0);
    EXPECT_EQ(rig.last.tangential.norm(), 0.0);
    for (int s = 0; s < steps; ++s)
      rig.step(0.0, phi / steps);
    const double t_loaded = rig.last.tangential.norm();
    const double n_loaded = rig.last.normal_elastic;
    for (int s = 0; s < steps; ++s)
      rig.step((h1 - h0) / steps, 0.0);
    const double t_unloaded = rig.last.tangential.norm();
    const double expected_scale =
        walton ? std::cbrt(rig.last.normal_elastic / n_loaded) : 1.0; // K_T(h0)/K_T(h1)
    EXPECT_NEAR(t_unloaded / t_loaded, expected_scale, 1e-12);
    for (int s = 0; s < steps; ++s)
      rig.step(0.0, -phi / steps);
    EXPECT_NEAR(rig.x_j[0], 2 * kR - h0, 1e-18);
    work[walton] = rig.work;
    // Stored tangential energy left at the end, T²/(2 K_T0): dissipation = work - stored.
    const double k_t0 =
        rig.law.stiffness(make_pair_geometry<dim>(kR, kR, kMass, kMass, rig.x_j), rig.state).k_t;
    const double stored = rig.last.tangential.squaredNorm() / (2 * k_t0);
    if (walton) {
      EXPECT_GE(rig.work - stored, 0.0);
    } else {
      EXPECT_LT(rig.work - stored, 0.0);
    }
  }
  EXPECT_GT(work[1], 0.0); // with Walton: no energy created
  EXPECT_LT(work[0], 0.0); // without: the cycle returns energy it never received
  // Magnitudes: ±½ (K_T1 - K_T0) u², u = φ R (to O(h/R)).
  const double kt0 =
      TangentialElasticity::mindlin_ratio(kNu) * kE / (1 - kNu * kNu) * std::sqrt(kR / 2 * h0);
  const double kt1 = kt0 * std::sqrt(h1 / h0);
  const double w = 0.5 * (kt1 - kt0) * (phi * kR) * (phi * kR);
  EXPECT_NEAR(work[1] / w, 1.0, 0.01);
  EXPECT_NEAR(work[0] / -w, 1.0, 0.01);
}

namespace {

template <int dim> Eigen::Matrix<double, dim, dim> rotation_matrix(const RotVec<dim>& theta) {
  if constexpr (dim == 3) {
    const double a = theta.norm();
    return a > 0 ? Eigen::Matrix3d(Eigen::AngleAxisd(a, theta / a)) : Eigen::Matrix3d::Identity();
  } else {
    return Eigen::Rotation2Dd(theta[0]).toRotationMatrix();
  }
}

/// Loads a contact tangentially (μ = inf), then rotates the pair rigidly about its centre of
/// mass at angular velocity omega (grains spinning at omega too) for many small steps.
/// Checks N and |T| constant and T fixed in the rotating frame, within 1e-10.
template <int dim>
void check_rigid_rotation(const Vec<dim>& normal0, const RotVec<dim>& omega, bool walton = true,
                          int steps = 5000, double tol = 1e-10) {
  const double ri = kR, rj = 0.7 * kR, mi = kMass, mj = 0.34 * kMass, h = 3e-6;
  ContactLaw<dim> law = hertz_law<dim>(kInf, walton);
  law.damping.zeta = 0.5; // ḣ = 0 in a rigid motion: damping must not matter
  // Centre of mass at the origin: positions of the order of the radii keep rounding small.
  const Vec<dim> xi0 = -(mj / (mi + mj)) * (ri + rj - h) * normal0;
  const Vec<dim> xj0 = xi0 + (ri + rj - h) * normal0;
  ContactState<dim> st;
  // Tangential load: spin j for a few steps with the centres fixed.
  ContactKinematics<dim> load;
  if constexpr (dim == 3) {
    load.w_j = normal0.cross(Vec<3>(0.3, 0.5, -0.2)) * 50.0; // a rolling-axis spin
  } else {
    load.w_j[0] = 50.0;
  }
  ContactForces<dim> f;
  for (int s = 0; s < 5; ++s) // T0 about 0.4 N^e
    f = law.force(make_pair_geometry<dim>(ri, rj, mi, mj, xj0 - xi0), load, st, 1e-5);
  const Vec<dim> t0 = f.tangential;
  const double n0 = f.normal_elastic;
  ASSERT_GT(t0.norm(), 0.1 * n0);
  const Vec<dim> c = (mi * xi0 + mj * xj0) / (mi + mj);
  // ~3e-3 rad per step, 12-15 rad in total. Walton's rule (on, as by default) scales T down
  // whenever N^e decreases, also by rounding noise of h (~1e-14 relative per step here): that
  // one-sided ratchet, not transport, is what limits the number of steps at 1e-10.
  const double dt = 1e-5;
  double worst_n = 0, worst_t = 0, worst_dir = 0;
  for (int s = 1; s <= steps; ++s) {
    const Eigen::Matrix<double, dim, dim> rot = rotation_matrix<dim>(RotVec<dim>(omega * (s * dt)));
    const Vec<dim> xi = c + rot * (xi0 - c), xj = c + rot * (xj0 - c);
    ContactKinematics<dim> kin;
    kin.v_i = spin_velocity<dim>(omega, Vec<dim>(xi - c));
    kin.v_j = spin_velocity<dim>(omega, Vec<dim>(xj - c));
    kin.w_i = omega;
    kin.w_j = omega;
    f = law.force(make_pair_geometry<dim>(ri, rj, mi, mj, xj - xi), kin, st, dt);
    worst_n = std::max(worst_n, std::abs(f.normal_total / n0 - 1));
    worst_t = std::max(worst_t, std::abs(f.tangential.norm() / t0.norm() - 1));
    worst_dir = std::max(worst_dir, (rot.transpose() * f.tangential - t0).norm() / t0.norm());
  }
  std::printf("rigid rotation dim %d: max rel. error N %.2e |T| %.2e direction %.2e\n", dim,
              worst_n, worst_t, worst_dir);
  EXPECT_LT(worst_n, tol);
  EXPECT_LT(worst_t, tol);
  EXPECT_LT(worst_dir, tol);
  EXPECT_FALSE(st.flags & kSliding);
}

} // namespace

TEST(ContactObjectivity, RigidRotationOfPairIn2D) {
  RotVec<2> w;
  w << 300.0;
  check_rigid_rotation<2>(Vec<2>(0.6, 0.8), w);
}

TEST(ContactObjectivity, RigidRotationOfPairIn3DGenericAxis) {
  check_rigid_rotation<3>(Vec<3>(0.36, -0.48, 0.8), Vec<3>(120.0, -200.0, 90.0));
}

TEST(ContactObjectivity, PivotingAboutTheNormalIn3D) {
  const Vec<3> n(0.36, -0.48, 0.8);
  check_rigid_rotation<3>(n, Vec<3>(250.0 * n)); // pure pivoting: centres do not move
}

TEST(ContactObjectivity, RollingAboutAnAxisNormalToTheContactIn3D) {
  const Vec<3> n(0.0, 0.0, 1.0);
  check_rigid_rotation<3>(n, Vec<3>(0.0, 250.0, 0.0));
}

// Transport alone (Walton off): exact up to rounding over many more steps (~60 rad).
TEST(ContactObjectivity, TransportAloneIsExactUpToRounding) {
  check_rigid_rotation<3>(Vec<3>(0.36, -0.48, 0.8), Vec<3>(120.0, -200.0, 90.0), false, 50000,
                          5e-11);
  RotVec<2> w;
  w << 300.0;
  check_rigid_rotation<2>(Vec<2>(0.6, 0.8), w, false, 50000, 5e-11);
}
