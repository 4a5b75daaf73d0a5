// The derived contact constants (contact/derived_constants.h) and the Hertz inversions the
// time steps use: closed forms, the F1 rule with and without cohesion, the rattler rule.
#include <gtest/gtest.h>

#include <cmath>

#include "granpack/contact/contact_law_params.h"
#include "granpack/contact/derived_constants.h"

using namespace granpack;

TEST(ContactDerivedConstants, ETildeIsTheModulusOfTheHertzLaw) {
  EXPECT_DOUBLE_EQ(e_tilde_of(70e9, 0.3), 70e9 / 0.91);
  EXPECT_EQ(e_tilde_of(1.0, 0.0), 1.0);
  ContactLawParams p;
  p.young_modulus = 2.88e8;
  p.poisson_ratio = 0.3;
  const auto law = make_contact_law<3>(p);
  // The factory builds the law from the same function, bit for bit.
  EXPECT_EQ(std::get<HertzNormal>(law.normal).e_tilde, e_tilde_of(2.88e8, 0.3));
}

TEST(ContactDerivedConstants, EqualGrainConventions) {
  const double a = 1e-3, m = 1.3e-6;
  const double r = 0.5 * a;
  EXPECT_DOUBLE_EQ(equal_grains_effective_radius(a), r * r / (r + r));
  EXPECT_DOUBLE_EQ(equal_grains_effective_mass(m), m * m / (m + m));
  EXPECT_EQ(grain_section(3, a), a * a);
  EXPECT_EQ(grain_section(2, a), a);
  EXPECT_EQ(pressure_force(3, a, 1e4), a * a * 1e4);
  EXPECT_EQ(pressure_force(2, a, 10.0), 10.0 * a);
}

TEST(ContactDerivedConstants, ForceScaleF1) {
  const double a = 1e-3;
  // Without cohesion: [AR]'s a^2 P, and P a^(dim-1) itself even for P <= 0.
  EXPECT_EQ(force_scale_f1(3, a, 1e4, 0.0), a * a * 1e4);
  EXPECT_EQ(force_scale_f1(2, a, -5.0, 0.0), -5.0 * a);
  EXPECT_EQ(force_scale_f1(2, a, 0.0, 0.0), 0.0);
  // With cohesion: max(F0, P a^(dim-1)).
  EXPECT_EQ(force_scale_f1(2, a, 10.0, 1.0), 1.0);    // P* = 0.01
  EXPECT_EQ(force_scale_f1(2, a, 0.0, 1.0), 1.0);     // P* = 0
  EXPECT_EQ(force_scale_f1(2, a, 1e4, 1.0), 1e4 * a); // P* = 10
  EXPECT_EQ(force_scale_f1(3, a, -1.0, 2.0), 2.0);
}

TEST(ContactDerivedConstants, MinimumBackboneContacts) {
  EXPECT_EQ(min_backbone_contacts(3, 0.0), 4);
  EXPECT_EQ(min_backbone_contacts(2, 0.0), 3);
  EXPECT_EQ(min_backbone_contacts(3, 0.3), 2);
  EXPECT_EQ(min_backbone_contacts(2, 1e-9), 2);
}

TEST(ContactDerivedConstants, HertzInversionsAndStiffnessNumber) {
  const double e_tilde = e_tilde_of(70e9, 0.3), r_eff = 0.25e-3, force = 1e-2;
  const double h = hertz_overlap_at_force(e_tilde, r_eff, force);
  const NormalResponse nr = HertzNormal{e_tilde}.response(h, r_eff);
  EXPECT_NEAR(nr.force, force, 1e-14 * force);
  EXPECT_EQ(hertz_stiffness_at_force(e_tilde, r_eff, force), nr.stiffness);
  // kappa = (E~/P)^(2/3): a^2 P = N gives h/a ~ 1/kappa for equal spheres ([AR] eq. 21).
  EXPECT_NEAR(hertz_stiffness_number(1e9, 1e3), 1e4, 1e-8);
  // With the dimension: 3D the same; 2D, P = 1e3 N/m on grains of a = 1 mm is the force
  // P a = 1 N per grain, and E~ a = 1e6 N/m gives (E~ a / P)^(2/3) = 100, not (E~/P)^(2/3).
  EXPECT_NEAR(hertz_stiffness_number(1e9, 1e-3, 3, 1e3), 1e4, 1e-8);
  EXPECT_NEAR(hertz_stiffness_number(1e9, 1e-3, 2, 1e3), 100.0, 1e-10);
  // [GRC]'s cohesive kappa: F0 = E~ a^2 / 1000 gives 1000^(2/3) = 100, in 2D and 3D alike.
  EXPECT_NEAR(hertz_cohesive_stiffness_number(1e9, 1e-3, 1.0), 100.0, 1e-10);
}
