// Contact law, [GRC] parts: cohesion (eq. 4-5, 7, 8, 11) and rolling resistance (eq. 9-10),
// in 2D and 3D, in the reduced units of [GRC] (a = 1, mass of a grain of diameter a = 1,
// F0 = 1) with the parameters of its table I (docs/contact-law.md).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

#include "granpack/contact/contact_law.h"
#include "granpack/contact/contact_law_params.h"

using namespace granpack;

namespace {

constexpr double kA = 1.0, kR = 0.5 * kA, kMass = 1.0, kF0 = 1.0;
constexpr double kKn = 1e4 * kF0 / kA; // kappa = a K_N / F0 = 1e4
constexpr double kD0 = 1e-3 * kA;
constexpr double kH0 = kF0 / kKn; // eq. (11)

ContactLawParams cohesive_params(double mu, double zeta) {
  ContactLawParams p;
  p.normal = NormalLawKind::kLinear;
  p.k_n = kKn;
  p.tangential = TangentialStiffnessKind::kRatio;
  p.k_t_ratio = 1.0;
  p.friction = mu;
  p.damping_ratio = zeta;
  p.cohesion_force = kF0;
  p.cohesion_range = kD0;
  return p;
}

template <int dim> Vec<dim> along_x(double x) {
  Vec<dim> v = Vec<dim>::Zero();
  v[0] = x;
  return v;
}

template <int dim> RotVec<dim> about_z(double w) {
  RotVec<dim> r = RotVec<dim>::Zero();
  r[rot_dim<dim> - 1] = w;
  return r;
}

/// Grain i at the origin, j on the x axis at overlap h, both at rest.
template <int dim> PairGeometry<dim> pair_at(double h) {
  return make_pair_geometry<dim>(kR, kR, kMass, kMass, along_x<dim>(2 * kR - h));
}

/// Head-on motion of two equal grains along x, velocity Verlet with half-step velocities in
/// the force (as the engine). Starts at overlap h_start with relative normal velocity
/// v_rel (> 0: receding). Returns the overlap after `steps` steps, or stops early once the
/// gap exceeds D0 while the grains still recede (they have escaped: no force acts beyond
/// D0) and returns that gap as -h.
template <int dim> struct HeadOn {
  ContactLaw<dim> law;
  double dt;
  ContactState<dim> state;
  double escaped_at = -1; // time of escape, or -1

  double run(double h_start, double v_rel, long steps) {
    Vec<dim> xi = Vec<dim>::Zero(), xj = along_x<dim>(2 * kR - h_start);
    Vec<dim> vi = along_x<dim>(-0.5 * v_rel), vj = along_x<dim>(0.5 * v_rel);
    Vec<dim> fj = Vec<dim>::Zero();
    double h = h_start;
    for (long s = 0; s < steps; ++s) {
      vi -= (0.5 * dt / kMass) * fj;
      vj += (0.5 * dt / kMass) * fj;
      xi += dt * vi;
      xj += dt * vj;
      const PairGeometry<dim> g = make_pair_geometry<dim>(kR, kR, kMass, kMass, Vec<dim>(xj - xi));
      ContactKinematics<dim> kin;
      kin.v_i = vi;
      kin.v_j = vj;
      fj = law.force(g, kin, state, dt).force_on_j;
      vi -= (0.5 * dt / kMass) * fj;
      vj += (0.5 * dt / kMass) * fj;
      h = g.overlap;
      if (-h > kD0 && (vj - vi)[0] > 0) {
        escaped_at = s * dt;
        return h;
      }
    }
    return h;
  }
};

} // namespace

template <typename T> class ContactCohesionTest : public ::testing::Test {};
template <int d> struct Dim { static constexpr int value = d; };
using Dims = ::testing::Types<Dim<2>, Dim<3>>;
TYPED_TEST_SUITE(ContactCohesionTest, Dims);

// [GRC] fig. 1a: the static normal force N^e + N^a against h, continuous at contact (-F0),
// linear attraction across gaps up to D0, nothing beyond; its slope K_N in contact and
// -F0/D0 across a gap; distant pairs carry no tangential force and are flagged kDistant.
TYPED_TEST(ContactCohesionTest, ForceDistanceLawOfFigure1) {
  constexpr int dim = TypeParam::value;
  const ContactLaw<dim> law = make_contact_law<dim>(cohesive_params(0.5, 0.0));
  EXPECT_EQ(law.interaction_range(), kD0);
  for (int k = -300; k <= 300; ++k) {
    const double h = k * (kD0 / 200); // gaps up to 1.5 D0, overlaps up to 1.5 D0 = 15 h0
    const PairGeometry<dim> g = pair_at<dim>(h);
    ContactState<dim> st;
    const ContactForces<dim> f = law.force(g, ContactKinematics<dim>{}, st, 1e-6);
    double expected;
    if (h > 0)
      expected = kKn * g.overlap - kF0;
    else if (-g.overlap < kD0)
      expected = -kF0 * (1 + g.overlap / kD0);
    else
      expected = 0;
    SCOPED_TRACE("h/D0 = " + std::to_string(h / kD0));
    EXPECT_NEAR(f.normal_total, expected, 1e-12 * kF0);
    EXPECT_NEAR(f.force_on_j[0], expected, 1e-12 * kF0); // n = +x, nothing tangential
    EXPECT_NEAR(f.normal_elastic + f.normal_attractive, expected, 1e-12 * kF0);
    EXPECT_EQ(f.active, -g.overlap < kD0);
    const ContactStiffness ks = law.stiffness(g, st);
    if (h > 0) {
      EXPECT_EQ(ks.k_n, kKn);
      EXPECT_EQ(ks.k_t, kKn);
      EXPECT_FALSE(ks.distant);
      EXPECT_EQ(st.flags & kDistant, 0u);
    } else if (-g.overlap < kD0) {
      EXPECT_DOUBLE_EQ(ks.k_n, -kF0 / kD0);
      EXPECT_EQ(ks.k_t, 0.0);
      EXPECT_TRUE(ks.distant);
      EXPECT_EQ(st.flags, static_cast<std::uint32_t>(kDistant));
      EXPECT_EQ(st.age, 1);
    } else {
      EXPECT_EQ(ks.k_n, 0.0);
      EXPECT_EQ(st.age, 0);
    }
  }
  // Continuity at contact: -F0 from both sides.
  EXPECT_NEAR(law.attraction(1e-15), -kF0, 0.0);
  EXPECT_NEAR(law.attraction(-1e-15), -kF0, 1e-11);
}

// Coulomb acts on N^e only ([GRC] eq. 8): at the isolated equilibrium deflection h0 the
// total normal force vanishes, yet the contact holds a tangential force up to mu F0.
// A contact that opens forgets its tangential history (distant interaction: normal only).
TYPED_TEST(ContactCohesionTest, CoulombOnTheElasticPartAndHistoryLostWhenTheContactOpens) {
  constexpr int dim = TypeParam::value;
  const double mu = 0.5;
  const ContactLaw<dim> law = make_contact_law<dim>(cohesive_params(mu, 0.0));
  const PairGeometry<dim> g = pair_at<dim>(kH0);
  ContactState<dim> st;
  ContactKinematics<dim> slip;
  slip.v_j[1] = 1e-6; // j slides along +y
  ContactForces<dim> f;
  for (int s = 0; s < 200; ++s)
    f = law.force(g, slip, st, 1.0);
  EXPECT_NEAR(f.normal_total, 0.0, 1e-12); // N^e + N^a = K_N h0 - F0
  EXPECT_NEAR(f.normal_elastic, kF0, 1e-12);
  EXPECT_NEAR(-f.tangential[1], mu * kF0, 1e-12); // on the cone of N^e, not of N^e - F0
  EXPECT_TRUE(st.flags & kSliding);
  // Open the contact to a gap D0/2: a distant interaction, T and its history gone.
  f = law.force(pair_at<dim>(-0.5 * kD0), slip, st, 1.0);
  EXPECT_TRUE(f.active);
  EXPECT_EQ(f.tangential.norm(), 0.0);
  EXPECT_EQ(st.tangential_force.norm(), 0.0);
  EXPECT_EQ(st.flags, static_cast<std::uint32_t>(kDistant));
  EXPECT_NEAR(f.force_on_j[0], -0.5 * kF0, 1e-12);
  EXPECT_EQ(f.torque_i.norm() + f.torque_j.norm(), 0.0);
}

// Eq. (11): an isolated pair, released at rest across a gap D0/2, is pulled into contact and
// settles at the deflection h0 = F0/K_N (damping zeta = 0.8 of table I).
TYPED_TEST(ContactCohesionTest, IsolatedPairSettlesAtDeflectionH0) {
  constexpr int dim = TypeParam::value;
  HeadOn<dim> pair{make_contact_law<dim>(cohesive_params(0.5, 0.8)), 0.0, {}};
  const double t_c = M_PI * std::sqrt(0.5 * kMass / kKn); // contact duration, m* = m/2
  pair.dt = t_c / 200;
  const double h = pair.run(-0.5 * kD0, 0.0, 400'000); // 2000 contact durations
  std::printf("dim %d: settled at h = %.12e, h0 = %.12e\n", dim, h, kH0);
  EXPECT_NEAR(h / kH0, 1.0, 1e-9);
  EXPECT_LT(pair.escaped_at, 0);
}

// Eq. (7): two grains leaving contact (zero gap) with relative velocity v escape the
// attraction only if (1/2) m* v^2 > F0 D0 / 2, i.e. v > sqrt(F0 D0 / m*) = V* sqrt(2) for
// unit masses. 1 % below the threshold they fall back into contact, 1 % above they escape.
TYPED_TEST(ContactCohesionTest, GrainsSeparateOnlyAboveTheEscapeVelocityOfEq7) {
  constexpr int dim = TypeParam::value;
  const ContactLaw<dim> law = make_contact_law<dim>(cohesive_params(0.5, 0.8));
  const double v_star = std::sqrt(kF0 * kD0); // eq. (7)
  const double v_escape = law.cohesion->escape_velocity(0.5 * kMass);
  EXPECT_NEAR(v_escape, v_star * std::sqrt(2.0), 1e-15);
  for (double factor : {0.99, 1.01}) {
    HeadOn<dim> pair{law, (kD0 / v_escape) / 1e5, {}}; // 1e5 steps to cross the range
    const double h = pair.run(-1e-12 * kD0, factor * v_escape, 2'000'000);
    std::printf("dim %d: v/v_escape = %.2f: escaped %d, final h/D0 = %.4g\n", dim, factor,
                pair.escaped_at >= 0, h / kD0);
    if (factor > 1) {
      EXPECT_GE(pair.escaped_at, 0);
    } else {
      EXPECT_LT(pair.escaped_at, 0);
      EXPECT_GT(h, 0); // back in contact
    }
  }
}

// [GRC] eq. 9-10 at the contact law: the rolling moment on j is -K_r dtheta while
// |K_r dtheta| < mu_r N^e, holds at mu_r N^e with kRollingPlastic once reached, and unloads
// elastically; the moment on i is the opposite. Frictionless (mu = 0): the spin of j slips
// its contact point, and the torque is then the rolling moment alone.
TYPED_TEST(ContactCohesionTest, RollingMomentElasticThenOnItsThreshold) {
  constexpr int dim = TypeParam::value;
  ContactLawParams p = cohesive_params(0.0, 0.0);
  p.rolling_stiffness = 1e-4 * kA * kA * kKn; // table I
  p.rolling_friction = 1e-2 * 0.5 * kA;       // table I: mu_r = 1e-2 mu a with mu = 0.5
  const ContactLaw<dim> law = make_contact_law<dim>(p);
  const PairGeometry<dim> g = pair_at<dim>(2 * kH0);
  const double n_e = kKn * 2 * kH0, limit = p.rolling_friction * n_e;
  // 1000 increments reach 0.9995 of the limit, the 1001st would pass it by 0.05 %.
  const double step = limit / p.rolling_stiffness / 1000.5;
  ContactState<dim> st;
  ContactKinematics<dim> kin;
  kin.w_j = about_z<dim>(step); // dt = 1
  double moment = 0;
  int first_plastic = -1;
  for (int s = 1; s <= 1500; ++s) {
    const ContactForces<dim> f = law.force(g, kin, st, 1.0);
    moment = f.torque_j[rot_dim<dim> - 1];
    EXPECT_DOUBLE_EQ(f.torque_i[rot_dim<dim> - 1], -moment);
    if (first_plastic < 0 && (st.flags & kRollingPlastic))
      first_plastic = s;
    if (first_plastic < 0)
      EXPECT_NEAR(moment, -p.rolling_stiffness * s * step, 1e-12 * limit);
    else
      EXPECT_NEAR(moment, -limit, 1e-12 * limit);
  }
  EXPECT_EQ(first_plastic, 1001);
  // Reverse the spin: elastic unloading by K_r per radian, flag cleared.
  kin.w_j = about_z<dim>(-step);
  const ContactForces<dim> f = law.force(g, kin, st, 1.0);
  EXPECT_NEAR(f.torque_j[rot_dim<dim> - 1], -limit + p.rolling_stiffness * step, 1e-12 * limit);
  EXPECT_FALSE(st.flags & kRollingPlastic);
  EXPECT_EQ(law.stiffness(g, st).k_r, p.rolling_stiffness);
}

// A grain j held at its centre in contact with a fixed grain i (frictionless, so the
// contact transmits no tangential force), under an applied torque growing slowly from zero:
// it stays put, its rotation resisted by the rolling moment, until the torque reaches
// mu_r N^e, and rolls from then on. The ramp takes 1000 rotational periods sqrt(I/K_r),
// so the elastic response lags the torque by at most dGamma/dt sqrt(I/K_r) = 1e-3 mu_r N^e.
TYPED_TEST(ContactCohesionTest, PairUnderGrowingTorqueStartsRollingAtMuRNe) {
  constexpr int dim = TypeParam::value;
  ContactLawParams p = cohesive_params(0.0, 0.0);
  p.rolling_stiffness = 1e-4 * kA * kA * kKn;
  p.rolling_friction = 1e-2 * 0.5 * kA;
  const ContactLaw<dim> law = make_contact_law<dim>(p);
  const PairGeometry<dim> g = pair_at<dim>(3 * kH0);
  const double n_e = kKn * 3 * kH0, limit = p.rolling_friction * n_e;
  const double inertia = kMass * kA * kA / (dim == 2 ? 8.0 : 10.0); // disk / sphere
  const double period = std::sqrt(inertia / p.rolling_stiffness);
  const double ramp = limit / (1000 * period); // dGamma/dt
  const double dt = period / 100;
  ContactState<dim> st;
  ContactKinematics<dim> kin;
  double w = 0, torque_contact = 0, t = 0, yield_torque = -1;
  for (long s = 0; s < 300'000 && yield_torque < 0; ++s) {
    // Velocity Verlet on the spin of j; the contact sees the half-step spin.
    const double applied = ramp * t;
    w += 0.5 * dt * (applied + torque_contact) / inertia;
    t += dt;
    kin.w_j = about_z<dim>(w);
    const ContactForces<dim> f = law.force(g, kin, st, dt);
    torque_contact = f.torque_j[rot_dim<dim> - 1];
    w += 0.5 * dt * (ramp * t + torque_contact) / inertia;
    if (st.flags & kRollingPlastic)
      yield_torque = ramp * t;
  }
  std::printf("dim %d: yield at applied torque %.9g, mu_r N^e %.9g (ratio %.6f)\n", dim,
              yield_torque, limit, yield_torque / limit);
  ASSERT_GT(yield_torque, 0);
  EXPECT_NEAR(yield_torque / limit, 1.0, 2e-3);
}

// In 3D only the rolling components resist: pivoting about n produces no rolling moment,
// and a rigid rotation of the pair (both grains spinning with the pair) neither creates a
// rolling moment nor changes a stored one, which turns with the contact.
TEST(ContactRolling3D, PivotingIsFreeAndRigidRotationIsObjective) {
  ContactLawParams p = cohesive_params(0.5, 0.0);
  p.rolling_stiffness = 1e-4 * kA * kA * kKn;
  p.rolling_friction = 1e-2 * 0.5 * kA;
  const ContactLaw<3> law = make_contact_law<3>(p);
  {
    ContactState<3> st;
    ContactKinematics<3> kin;
    kin.w_j = Vec<3>(1e-3, 0, 0); // about n = +x
    const ContactForces<3> f = law.force(pair_at<3>(kH0), kin, st, 1.0);
    EXPECT_EQ(st.rolling.norm(), 0.0);
    EXPECT_EQ((f.torque_j + f.torque_i).norm(), 0.0);
  }
  // Preload a rolling rotation about z, then rotate the pair rigidly about an axis that is
  // neither n nor the preload.
  const double h = 2 * kH0;
  ContactState<3> st;
  ContactKinematics<3> kin;
  kin.w_j = Vec<3>(0, 0, 1e-4);
  law.force(pair_at<3>(h), kin, st, 1.0);
  const double stored = st.rolling.norm();
  ASSERT_GT(stored, 0);
  const Vec<3> axis = Vec<3>(0.3, -0.5, 0.8).normalized();
  const double omega = 2.0, dt = 1e-4;
  const Vec<3> r0(2 * kR - h, 0, 0);
  for (int s = 1; s <= 20000; ++s) { // 4 rad
    const Eigen::AngleAxisd rot(omega * dt * s, axis);
    const Vec<3> r = rot * r0;
    ContactKinematics<3> rigid;
    rigid.v_j = omega * axis.cross(r); // i at the origin, the pair turning about i
    rigid.w_i = rigid.w_j = omega * axis;
    law.force(make_pair_geometry<3>(kR, kR, kMass, kMass, r), rigid, st, dt);
    const Vec<3> expected = rot * Vec<3>(0, 0, stored);
    ASSERT_NEAR((st.rolling - expected).norm(), 0.0, 1e-9 * stored) << "step " << s;
  }
  EXPECT_NEAR(st.rolling.norm(), stored, 1e-12 * stored);
}

// The optional rolling damping (not in [GRC]): a grain spinning on the rolling spring of a
// contact with a fixed grain (frictionless, centre held) is a damped rotational oscillator,
// I dw/dt = -K_r theta - eta_r w with eta_r = zeta_r 2 R* sqrt(m* K_r). Successive maxima of
// theta shrink by exp(-2 pi z / sqrt(1 - z^2)), z = eta_r / (2 sqrt(I K_r)); without damping
// they do not shrink at all (no other dissipation acts on the spin).
TYPED_TEST(ContactCohesionTest, RollingDampingGivesTheDampedOscillatorDecrement) {
  constexpr int dim = TypeParam::value;
  for (double zeta_r : {0.0, 0.05}) {
    ContactLawParams p = cohesive_params(0.0, 0.0);
    p.rolling_stiffness = 1e-4 * kA * kA * kKn;
    p.rolling_friction = kA; // far above any moment reached here
    p.rolling_damping = zeta_r;
    const ContactLaw<dim> law = make_contact_law<dim>(p);
    const PairGeometry<dim> g = pair_at<dim>(kH0);
    const double inertia = kMass * kA * kA / (dim == 2 ? 8.0 : 10.0);
    const double eta = law.rolling->viscosity(g.effective_mass, g.effective_radius);
    EXPECT_DOUBLE_EQ(eta, zeta_r * 2 * g.effective_radius *
                              std::sqrt(g.effective_mass * p.rolling_stiffness));
    const double z = eta / (2 * std::sqrt(inertia * p.rolling_stiffness));
    const double period = 2 * M_PI * std::sqrt(inertia / p.rolling_stiffness);
    const double dt = period / 20000;
    ContactState<dim> st;
    ContactKinematics<dim> kin;
    double w = 1e-3, torque = 0, prev = 0, prev2 = 0;
    std::vector<double> maxima;
    for (long s = 0; s < 100000 && maxima.size() < 3; ++s) {
      w += 0.5 * dt * torque / inertia;
      kin.w_j = about_z<dim>(w);
      torque = law.force(g, kin, st, dt).torque_j[rot_dim<dim> - 1];
      w += 0.5 * dt * torque / inertia;
      const double theta = st.rolling[rot_dim<dim> - 1];
      if (s >= 2 && prev > prev2 && prev >= theta && prev > 0)
        maxima.push_back(prev);
      prev2 = prev;
      prev = theta;
    }
    ASSERT_EQ(maxima.size(), 3u);
    const double expected = std::exp(-2 * M_PI * z / std::sqrt(1 - z * z));
    std::printf("dim %d zeta_r %.2f: z %.5f, maxima ratio %.6f, expected %.6f\n", dim, zeta_r, z,
                maxima[2] / maxima[1], expected);
    EXPECT_NEAR(maxima[2] / maxima[1], expected, 1e-3);
    if (zeta_r == 0) {
      EXPECT_NEAR(maxima[2] / maxima[1], 1.0, 1e-6);
    }
  }
}
