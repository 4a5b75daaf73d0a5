// Two-grain head-on collisions integrated with velocity Verlet through ContactLaw::force:
// Hertz contact duration and restitution vs ζ (3D glass spheres), linear damped oscillator
// in 2D and 3D (docs/contact-law.md, SPEC §8 step 2).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "granpack/contact/collision_times.h"
#include "granpack/contact/contact_law.h"
#include "granpack/contact/contact_law_params.h"

using namespace granpack;

namespace {

struct Collision {
  bool separated = false;
  double duration = 0;    // time with h > 0 (crossings interpolated linearly)
  double restitution = 0; // -(separation velocity) / (approach velocity), at the end
  double min_normal = 0;  // smallest total normal force N^e + N^v during the contact
};

/// Grain i at rest, j approaching along -n at speed v (equal radii r and masses m). The gap at
/// t = 0 is v dt / 2, so contact starts within the first step. Velocity Verlet; forces use the
/// half-step velocities (as the engine does). Stops at separation or after max_steps.
template <int dim>
Collision collide(const ContactLaw<dim>& law, double r, double m, double v, double dt,
                  long max_steps = 1'000'000) {
  Vec<dim> n = Vec<dim>::Zero();
  n[0] = 0.6;
  n[1] = 0.8;
  Vec<dim> xi = Vec<dim>::Zero(), xj = (2 * r + 0.5 * v * dt) * n;
  Vec<dim> vi = Vec<dim>::Zero(), vj = -v * n;
  Vec<dim> fj = Vec<dim>::Zero();
  ContactState<dim> st;
  double h_prev = 2 * r - (xj - xi).norm(), t = 0, t_start = -1, t_end = -1, min_normal = 0;
  for (long s = 0; s < max_steps && t_end < 0; ++s) {
    vi -= (0.5 * dt / m) * fj;
    vj += (0.5 * dt / m) * fj;
    xi += dt * vi;
    xj += dt * vj;
    t += dt;
    const PairGeometry<dim> g = make_pair_geometry<dim>(r, r, m, m, Vec<dim>(xj - xi));
    ContactKinematics<dim> kin;
    kin.v_i = vi;
    kin.v_j = vj;
    const ContactForces<dim> f = law.force(g, kin, st, dt);
    fj = f.force_on_j;
    if (f.active)
      min_normal = std::min(min_normal, f.normal_total);
    vi -= (0.5 * dt / m) * fj;
    vj += (0.5 * dt / m) * fj;
    const double h = g.overlap;
    if (t_start < 0 && h > 0)
      t_start = t - dt * h / (h - h_prev);
    if (t_start >= 0 && h <= 0)
      t_end = t - dt * h / (h - h_prev);
    h_prev = h;
  }
  return {t_end > 0, t_end - t_start, (vj - vi).dot(n) / v, min_normal};
}

constexpr double kE = 70e9, kNu = 0.3, kRho = 2500, kD = 1e-3;

ContactLaw<3> glass_law(double zeta, bool tension = true) {
  ContactLawParams p;
  p.young_modulus = kE;
  p.poisson_ratio = kNu;
  p.damping_ratio = zeta;
  p.damping_tension = tension;
  p.friction = 0.3;
  return make_contact_law<3>(p);
}

} // namespace

TEST(ContactCollision, HertzDurationAndElasticRestitutionOfGlassSpheres) {
  const double r = kD / 2, m = kRho * std::numbers::pi * kD * kD * kD / 6;
  const double e_tilde = kE / (1 - kNu * kNu);
  for (double v : {0.01, 1.0}) {
    const double tau = hertz_contact_duration(e_tilde, r / 2, m / 2, v);
    const Collision c = collide<3>(glass_law(0.0), r, m, v, tau / 2000);
    std::printf("Hertz V=%g: tau %.6e s, measured %.6e s (ratio %.6f), e %.8f\n", v, tau,
                c.duration, c.duration / tau, c.restitution);
    ASSERT_TRUE(c.separated);
    EXPECT_NEAR(c.duration / tau, 1.0, 0.01);
    EXPECT_NEAR(c.restitution, 1.0, 1e-3);
  }
}

// α = 2ζ sqrt(m* K_N(h)) ∝ h^{1/4}: the equation m* ḧ = -(2/3)Ẽ√R* h^{3/2} - α(h) ḣ is
// invariant under h -> λh, t -> λ^{-1/4} t, so e depends on ζ only, not on V.
// e vanishes at a finite ζ_c (between 0.90 and 0.95): at ζ = 0.98 (the paper's value) the
// grains never separate, h -> 0 and the relative velocity -> 0 (e = 0) within ~20 τ.
TEST(ContactCollision, HertzRestitutionDecreasesWithZetaAndIgnoresVelocity) {
  const double r = kD / 2, m = kRho * std::numbers::pi * kD * kD * kD / 6;
  const double e_tilde = kE / (1 - kNu * kNu);
  double previous = 1.0;
  for (double zeta : {0.05, 0.2, 0.5, 0.98}) {
    Collision c[2];
    int k = 0;
    for (double v : {0.01, 1.0}) {
      const double tau = hertz_contact_duration(e_tilde, r / 2, m / 2, v);
      c[k++] = collide<3>(glass_law(zeta), r, m, v, tau / 2000, 100'000); // 50 τ at most
    }
    std::printf("Hertz zeta=%.2f: e(V=0.01) %.6g, e(V=1) %.6g, separated %d %d\n", zeta,
                c[0].restitution, c[1].restitution, c[0].separated, c[1].separated);
    EXPECT_LT(c[1].restitution, previous);
    if (zeta < 0.9) {
      ASSERT_TRUE(c[0].separated && c[1].separated);
      EXPECT_NEAR(c[0].restitution / c[1].restitution, 1.0, 0.01);
    } else {
      EXPECT_FALSE(c[0].separated || c[1].separated);
      EXPECT_NEAR(c[0].restitution, 0.0, 1e-6);
      EXPECT_NEAR(c[1].restitution, 0.0, 1e-6);
    }
    previous = c[1].restitution;
  }
}

// With the damping not allowed to pull (damping_tension = false, N^v >= -N^e), the unloading
// grains are never held back: they separate at every ζ, ζ = 0.98 included, where the default
// law holds them together (e = 0 above); N^e + N^v never goes below 0; e still depends on ζ
// only (the clipped equation keeps the scaling h -> λh, t -> λ^{-1/4} t) and exceeds the
// default law's e at the same ζ, whose end-of-contact pull slows the separation.
TEST(ContactCollision, DampingWithoutTensionNeverPullsAndAlwaysSeparates) {
  const double r = kD / 2, m = kRho * std::numbers::pi * kD * kD * kD / 6;
  const double e_tilde = kE / (1 - kNu * kNu);
  for (double zeta : {0.2, 0.5, 0.98}) {
    Collision c[2];
    int k = 0;
    for (double v : {0.01, 1.0}) {
      const double tau = hertz_contact_duration(e_tilde, r / 2, m / 2, v);
      c[k++] = collide<3>(glass_law(zeta, false), r, m, v, tau / 2000, 100'000);
    }
    const double tau = hertz_contact_duration(e_tilde, r / 2, m / 2, 1.0);
    const Collision pulled = collide<3>(glass_law(zeta), r, m, 1.0, tau / 2000, 100'000);
    std::printf("Hertz zeta=%.2f without tension: e(V=0.01) %.6g, e(V=1) %.6g; with: %.6g, "
                "min N %.3g / %.3g\n",
                zeta, c[0].restitution, c[1].restitution, pulled.restitution, c[1].min_normal,
                pulled.min_normal);
    ASSERT_TRUE(c[0].separated && c[1].separated);
    EXPECT_GT(c[1].restitution, 0.0);
    EXPECT_NEAR(c[0].restitution / c[1].restitution, 1.0, 0.01);
    EXPECT_GT(c[1].restitution, pulled.restitution);
    EXPECT_GE(c[0].min_normal, 0.0);
    EXPECT_GE(c[1].min_normal, 0.0);
    EXPECT_LT(pulled.min_normal, 0.0); // the default law pulls at the end of the contact
  }
}

template <typename T> class ContactLinearCollisionTest : public ::testing::Test {};
template <int d> struct Dim { static constexpr int value = d; };
using Dims = ::testing::Types<Dim<2>, Dim<3>>;
TYPED_TEST_SUITE(ContactLinearCollisionTest, Dims);

// Linear spring with N^v = 2ζ sqrt(m* K_N) ḣ: damped oscillator of reduced mass m*, contact
// lasting π/(ω0 sqrt(1-ζ²)) (π sqrt(m*/K_N) for ζ = 0), e = exp(-ζπ/sqrt(1-ζ²)).
TYPED_TEST(ContactLinearCollisionTest, DurationAndRestitutionOfDampedOscillator) {
  constexpr int dim = TypeParam::value;
  const double r = kD / 2;
  const double m = dim == 2 ? kRho * std::numbers::pi * kD * kD / 4 // per unit thickness
                            : kRho * std::numbers::pi * kD * kD * kD / 6;
  const double k_n = dim == 2 ? 1e7 : 1e4;
  for (double zeta : {0.0, 0.05, 0.2, 0.5, 0.8}) {
    ContactLawParams p;
    p.normal = NormalLawKind::kLinear;
    p.k_n = k_n;
    p.tangential = TangentialStiffnessKind::kRatio;
    p.k_t_ratio = 0.5;
    p.damping_ratio = zeta;
    const ContactLaw<dim> law = make_contact_law<dim>(p);
    const double tau = damped_linear_contact_duration(k_n, m / 2, zeta);
    const Collision c = collide<dim>(law, r, m, 0.1, tau / 200000);
    const double e = linear_restitution(zeta);
    std::printf("linear dim %d zeta=%.2f: tau %.6e measured %.6e, e %.6f closed form %.6f\n", dim,
                zeta, tau, c.duration, c.restitution, e);
    ASSERT_TRUE(c.separated);
    EXPECT_NEAR(c.duration / tau, 1.0, 1e-3);
    EXPECT_NEAR(c.restitution / e, 1.0, 1e-3);
  }
  EXPECT_NEAR(damped_linear_contact_duration(k_n, m / 2, 0.0),
              std::numbers::pi * std::sqrt(m / 2 / k_n), 1e-18);
}
