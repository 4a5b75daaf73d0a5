// Contact law, static parts: pair geometry, Hertz and linear normal laws, stiffness ratios,
// damping coefficient, sign conventions, factory validation (docs/contact-law.md).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "granpack/contact/collision_times.h"
#include "granpack/contact/contact_law.h"
#include "granpack/contact/contact_law_params.h"

using namespace granpack;

namespace {

constexpr double kE = 70e9, kNu = 0.3;
const double kETilde = kE / (1.0 - kNu * kNu);

template <int dim> Vec<dim> unit_direction() {
  Vec<dim> d;
  if constexpr (dim == 3) {
    d << 0.36, -0.48, 0.8;
  } else {
    d << 0.6, -0.8;
  }
  return d;
}

template <int dim> ContactLaw<dim> hertz_law(double zeta = 0, double mu = 0.3) {
  ContactLawParams p;
  p.young_modulus = kE;
  p.poisson_ratio = kNu;
  p.damping_ratio = zeta;
  p.friction = mu;
  return make_contact_law<dim>(p);
}

template <typename T> class ContactGeometryTest : public ::testing::Test {};
template <int d> struct Dim { static constexpr int value = d; };
using Dims = ::testing::Types<Dim<2>, Dim<3>>;
TYPED_TEST_SUITE(ContactGeometryTest, Dims);

} // namespace

TYPED_TEST(ContactGeometryTest, NormalOverlapEffectiveRadiusMassAndBranches) {
  constexpr int dim = TypeParam::value;
  const double ri = 1.0, rj = 0.4, mi = 3.0, mj = 0.5, dist = 1.3;
  const Vec<dim> r = dist * unit_direction<dim>();
  const PairGeometry<dim> g = make_pair_geometry<dim>(ri, rj, mi, mj, r);
  EXPECT_NEAR((g.normal - unit_direction<dim>()).norm(), 0.0, 1e-15);
  EXPECT_NEAR(g.distance, dist, 1e-15);
  EXPECT_NEAR(g.overlap, 0.1, 1e-15);
  EXPECT_NEAR(g.effective_radius, 0.4 / 1.4, 1e-15);
  EXPECT_NEAR(g.effective_mass, 1.5 / 3.5, 1e-15);
  // Both branch vectors end at the same point (middle of the overlap): b_i - b_j = r_ij.
  EXPECT_NEAR((g.branch_i() - g.branch_j() - r).norm(), 0.0, 1e-15);
  EXPECT_NEAR(g.branch_i().norm(), ri - 0.05, 1e-15);
  const PairGeometry<dim> gap =
      make_pair_geometry<dim>(ri, rj, mi, mj, 1.5 * unit_direction<dim>());
  EXPECT_NEAR(gap.overlap, -0.1, 1e-15);
  EXPECT_FALSE(gap.touching());
}

TEST(ContactHertz, EqualSpheresMatchPaperEquations1And2) {
  const double a = 1e-3, h = 2e-6; // diameter, deflection
  const HertzNormal hz{kETilde};
  const double r_eff = (a / 2) * (a / 2) / a;
  const NormalResponse nr = hz.response(h, r_eff);
  const double n_paper = kETilde * std::sqrt(a) * std::pow(h, 1.5) / 3.0; // eq. (1)
  const double k_paper = kETilde * std::sqrt(a) * std::sqrt(h) / 2.0;     // eq. (2)
  const double k_of_n = std::cbrt(3.0) / 2.0 * std::pow(kETilde, 2.0 / 3.0) * std::cbrt(a) *
                        std::cbrt(n_paper); // eq. (2), N form
  EXPECT_NEAR(nr.force / n_paper, 1.0, 1e-14);
  EXPECT_NEAR(nr.stiffness / k_paper, 1.0, 1e-14);
  EXPECT_NEAR(nr.stiffness / k_of_n, 1.0, 1e-13);
}

TEST(ContactHertz, UnequalSpheresMatchJohnsonForm) {
  // Johnson: N = (4/3) E* sqrt(R*) h^{3/2}, 1/E* = 2 (1-ν²)/E for identical materials.
  const double ri = 1e-3, rj = 0.4e-3, h = 3e-6;
  const double e_star = 1.0 / (2.0 * (1.0 - kNu * kNu) / kE);
  const double r_eff = 1.0 / (1.0 / ri + 1.0 / rj);
  const PairGeometry<3> g = make_pair_geometry<3>(ri, rj, 1.0, 1.0, Vec<3>(0.0, ri + rj - h, 0.0));
  const NormalResponse nr = normal_response(HertzNormal{kETilde}, g.overlap, g.effective_radius);
  EXPECT_NEAR(nr.force / (4.0 / 3.0 * e_star * std::sqrt(r_eff) * std::pow(h, 1.5)), 1.0, 1e-9);
  EXPECT_NEAR(nr.stiffness / (2.0 * e_star * std::sqrt(r_eff * h)), 1.0, 1e-9);
}

TEST(ContactHertz, StiffnessIsDerivativeOfForce) {
  const HertzNormal hz{kETilde};
  const double r_eff = 0.3e-3;
  for (double h : {1e-8, 1e-7, 5e-6, 1e-5}) {
    const double dh = 1e-5 * h;
    const double fd =
        (hz.response(h + dh, r_eff).force - hz.response(h - dh, r_eff).force) / (2 * dh);
    EXPECT_NEAR(fd / hz.response(h, r_eff).stiffness, 1.0, 1e-8) << "h = " << h;
  }
  EXPECT_EQ(hz.response(0.0, r_eff).force, 0.0);
  EXPECT_EQ(hz.response(-1e-6, r_eff).stiffness, 0.0);
  // Walton ratio K_N(N1)/K_N(N0) = (N1/N0)^{1/3} equals the ratio at the deflections.
  const double h0 = 2e-6, h1 = 0.7e-6;
  EXPECT_NEAR(hz.stiffness_ratio(hz.response(h1, r_eff).force, hz.response(h0, r_eff).force),
              hz.response(h1, r_eff).stiffness / hz.response(h0, r_eff).stiffness, 1e-14);
}

TEST(ContactLinear, ForceAndConstantStiffness) {
  const LinearNormal lin{2.5e5};
  EXPECT_DOUBLE_EQ(lin.response(1e-6, 1.0).force, 0.25);
  EXPECT_DOUBLE_EQ(lin.response(1e-6, 1.0).stiffness, 2.5e5);
  EXPECT_EQ(lin.response(-1e-6, 1.0).force, 0.0);
  EXPECT_EQ(lin.stiffness_ratio(0.1, 0.3), 1.0);
}

TYPED_TEST(ContactGeometryTest, TangentialToNormalStiffnessRatioIsMindlin) {
  constexpr int dim = TypeParam::value;
  for (double nu : {0.0, 0.2, 0.3, 0.45}) {
    ContactLawParams p;
    p.young_modulus = kE;
    p.poisson_ratio = nu;
    const ContactLaw<dim> law = make_contact_law<dim>(p);
    const PairGeometry<dim> g =
        make_pair_geometry<dim>(1e-3, 0.6e-3, 1.0, 1.0, (1.6e-3 - 4e-6) * unit_direction<dim>());
    const ContactStiffness k = law.stiffness(g, ContactState<dim>{});
    EXPECT_NEAR(k.k_t / k.k_n, (2.0 - 2.0 * nu) / (2.0 - nu), 1e-15);
    EXPECT_NEAR(k.k_n, kE / (1 - nu * nu) * std::sqrt(g.effective_radius * 4e-6), 1e-6 * k.k_n);
    EXPECT_EQ(k.k_r, 0.0);
    EXPECT_FALSE(k.sliding);
  }
  EXPECT_NEAR(TangentialElasticity::mindlin_ratio(0.3), 1.4 / 1.7, 1e-15);
}

TEST(ContactDamping, EqualMassesGivePaperEquation5) {
  const double m = 2e-6, k = 3e5, zeta = 0.4;
  EXPECT_NEAR(NormalDamping{zeta}.coefficient(m * m / (2 * m), k), zeta * std::sqrt(2 * m * k),
              1e-15);
  EXPECT_EQ(NormalDamping{0.0}.coefficient(m, k), 0.0);
}

TYPED_TEST(ContactGeometryTest, SignConventionsAndMomentBalance) {
  constexpr int dim = TypeParam::value;
  const ContactLaw<dim> law = hertz_law<dim>(0.5, 0.3);
  const double ri = 1e-3, rj = 0.7e-3, h = 2e-6;
  const Vec<dim> n = unit_direction<dim>();
  const PairGeometry<dim> g = make_pair_geometry<dim>(ri, rj, 4e-6, 2e-6, (ri + rj - h) * n);
  Vec<dim> t = Vec<dim>::Zero(); // a tangent direction
  t[0] = -n[1];
  t[1] = n[0];
  ContactKinematics<dim> kin;
  kin.v_j = -0.01 * n + 1e-3 * t; // j approaches i and slides along +t
  ContactState<dim> st;
  const ContactForces<dim> f = law.force(g, kin, st, 1e-7);
  ASSERT_TRUE(f.active);
  const NormalResponse nr = normal_response(law.normal, h, g.effective_radius);
  EXPECT_NEAR(f.normal_elastic / nr.force, 1.0, 1e-9); // h from |r_ij|: rounding
  EXPECT_GT(f.normal_total, f.normal_elastic);         // approaching: ḣ > 0, N^v > 0
  EXPECT_GT(f.force_on_j.dot(n), 0.0);                 // repulsive on j along +n
  EXPECT_LT(f.tangential.dot(t), 0.0);                 // friction on j opposes its sliding
  EXPECT_NEAR(f.tangential.dot(n), 0.0, 1e-15 * f.tangential.norm());
  // Angular momentum balance: r_ij x F_j + torque_i + torque_j = 0.
  const RotVec<dim> total = moment<dim>(g.distance * n, f.force_on_j) + f.torque_i + f.torque_j;
  EXPECT_NEAR(total.norm(), 0.0, 1e-15 * g.distance * f.force_on_j.norm());
  EXPECT_EQ(st.age, 1);
  EXPECT_DOUBLE_EQ(st.normal_force, f.normal_elastic);
  // Separation: inactive, zero forces, history reset.
  const PairGeometry<dim> apart = make_pair_geometry<dim>(ri, rj, 4e-6, 2e-6, (ri + rj + h) * n);
  const ContactForces<dim> f2 = law.force(apart, kin, st, 1e-7);
  EXPECT_FALSE(f2.active);
  EXPECT_EQ(f2.force_on_j.norm(), 0.0);
  EXPECT_EQ(st.age, 0);
  EXPECT_EQ(st.tangential_force.norm(), 0.0);
  EXPECT_EQ(law.interaction_range(), 0.0);
  EXPECT_FALSE(law.interacts(apart));
}

TEST(ContactLawFactory, ValidatesParameters) {
  ContactLawParams p;
  p.young_modulus = kE;
  p.poisson_ratio = kNu;
  EXPECT_NO_THROW(make_contact_law<3>(p));
  auto bad = [&](auto edit) {
    ContactLawParams q = p;
    edit(q);
    EXPECT_THROW(make_contact_law<3>(q), InputError);
  };
  bad([](ContactLawParams& q) { q.young_modulus = 0; });
  bad([](ContactLawParams& q) { q.poisson_ratio = 0.5; });
  bad([](ContactLawParams& q) { q.damping_ratio = 1.0; });
  bad([](ContactLawParams& q) { q.damping_ratio = -0.1; });
  bad([](ContactLawParams& q) { q.friction = -1; });
  bad([](ContactLawParams& q) { q.friction = std::numeric_limits<double>::quiet_NaN(); });
  bad([](ContactLawParams& q) {
    q.normal = NormalLawKind::kLinear;
    q.k_n = 0;
  });
  p.friction = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(make_contact_law<2>(p).friction.unlimited());
  // Cohesion needs both F0 and D0; rolling friction needs a rolling stiffness.
  bad([](ContactLawParams& q) { q.cohesion_force = 1e-3; });
  bad([](ContactLawParams& q) { q.cohesion_range = 1e-6; });
  bad([](ContactLawParams& q) {
    q.cohesion_force = -1e-3;
    q.cohesion_range = 1e-6;
  });
  bad([](ContactLawParams& q) { q.rolling_friction = 1e-5; });
  bad([](ContactLawParams& q) { q.rolling_damping = 0.5; });
  bad([](ContactLawParams& q) {
    q.rolling_stiffness = 1;
    q.rolling_damping = 1.0;
  });
  bad([](ContactLawParams& q) { q.rolling_stiffness = -1; });
  bad([](ContactLawParams& q) {
    q.rolling_stiffness = 1;
    q.rolling_friction = std::numeric_limits<double>::quiet_NaN();
  });
  EXPECT_FALSE(make_contact_law<3>(p).cohesion.has_value());
  EXPECT_FALSE(make_contact_law<3>(p).rolling.has_value());
  p.cohesion_force = 1e-3;
  p.cohesion_range = 1e-6;
  p.rolling_stiffness = 1.0;
  p.rolling_friction = 1e-5;
  const ContactLaw<2> law = make_contact_law<2>(p);
  ASSERT_TRUE(law.cohesion && law.rolling);
  EXPECT_EQ(law.interaction_range(), 1e-6);
  EXPECT_EQ(law.rolling->mu_r, 1e-5);
}

TEST(ContactCollisionTimes, ClosedForms) {
  // 2 ∫_0^1 (1 - x^{5/2})^{-1/2} dx by Simpson after x = 1 - s² (regular integrand).
  const int n = 20000;
  double sum = 0;
  for (int k = 0; k <= n; ++k) {
    const double s = double(k) / n;
    const double g =
        k == 0 ? 2.0 / std::sqrt(2.5) : 2 * s / std::sqrt(1 - std::pow(1 - s * s, 2.5));
    sum += (k == 0 || k == n ? 1 : (k % 2 ? 4 : 2)) * g;
  }
  EXPECT_NEAR(hertz_duration_constant(), 2 * sum / (3.0 * n), 1e-9);
  EXPECT_NEAR(hertz_duration_constant(), 2.94328, 1e-5);
  // τ = 2.9432 (15 m*/(16 E* sqrt R*))^{2/5} V^{-1/5}
  const double m = 1e-6, r = 2.5e-4, v = 0.3, e_star = kETilde / 2;
  EXPECT_NEAR(
      hertz_contact_duration(kETilde, r, m, v) /
          (2.943275 * std::pow(15 * m / (16 * e_star * std::sqrt(r)), 0.4) * std::pow(v, -0.2)),
      1.0, 1e-6);
  EXPECT_NEAR(linear_contact_duration(4.0, 1.0), M_PI / 2, 1e-15);
  EXPECT_NEAR(linear_critical_time_step(4.0, 1.0), 1.0, 1e-15);
  EXPECT_NEAR(linear_restitution(0.0), 1.0, 1e-15);
}
