// The per-grain static stress tensor of the contact network (analysis/contact_network.h) on
// closed forms: two grains pressed together (uniaxial sigma along the branch), a triangular
// lattice under isotropic contact forces (sigma = 3 F d / (2 V) I per grain), and, on a random
// configuration with tangential forces across the periodic boundary, the two identities the
// tensor is defined to keep: tr(sigma_g)/dim = mean_stress_g and sum_g V_g sigma_g = the cell's
// virial sum_c f (x) r_12.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <utility>

#include "granpack/analysis/contact_network.h"
#include "granpack/contact/contact_law_params.h"
#include "lattice_fixtures.h"

namespace granpack {
namespace {

/// A linear law of unit stiffnesses, with rolling resistance K_r when k_r > 0.
template <int dim> ContactLaw<dim> linear_law(double k_r = 0) {
  ContactLawParams p;
  p.normal = NormalLawKind::kLinear;
  p.k_n = 1.0;
  p.tangential = TangentialStiffnessKind::kConstant;
  p.k_t = 1.0;
  p.rolling_stiffness = k_r;
  p.rolling_friction = k_r > 0 ? 1.0 : 0.0;
  return make_contact_law<dim>(p);
}

template <int dim> Particle<dim> grain(GlobalId id, const Vec<dim>& scaled, double radius) {
  Particle<dim> g;
  g.id = id;
  g.radius = radius;
  g.position = scaled;
  return g;
}

/// 40 grains of random radii at random places in a cell of 4 x 5 (x 6), and a contact between
/// every pair closer than 1.2 with random N and T (and, with `rolling`, rolling rotations).
template <int dim> struct RandomContacts {
  Cell<dim> cell;
  ParticleStore<dim> p;
  ContactStore<dim> c;
  static constexpr int n = 40;
  RandomContacts(std::mt19937_64& rng, bool tangential, bool rolling) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int a = 0; a < dim; ++a)
      cell.length[a] = 4.0 + a;
    for (int i = 0; i < n; ++i) {
      Vec<dim> s;
      for (int a = 0; a < dim; ++a)
        s[a] = u(rng);
      p.add_owned(grain<dim>(i, s, 0.3 + 0.4 * u(rng)));
    }
    for (int i = 0; i < n; ++i)
      for (int j = i + 1; j < n; ++j)
        if (cell.min_image(p.position[std::size_t(i)], p.position[std::size_t(j)]).norm() < 1.2) {
          ContactState<dim> st;
          st.normal_force = 2 * u(rng) - 0.5;
          for (int a = 0; a < dim && tangential; ++a)
            st.tangential_force[a] = u(rng) - 0.5;
          for (int a = 0; a < rot_dim<dim> && rolling; ++a)
            st.rolling[a] = u(rng) - 0.5;
          c.insert(ContactKey::of(i, j), st);
        }
  }
  /// The force on `second` of contact k and its branch vector r_12.
  std::pair<Vec<dim>, Vec<dim>> force_and_branch(std::size_t k) const {
    const std::size_t i = std::size_t(c.key(k).first), j = std::size_t(c.key(k).second);
    const Vec<dim> r = cell.min_image(p.position[i], p.position[j]);
    return {c.state(k).normal_force * r.normalized() + c.state(k).tangential_force, r};
  }
};

template <int dim> double component(const NetworkFields<dim>& f, std::size_t g, int a, int b) {
  return f.stress[std::size_t(a * dim + b)][g];
}

template <int dim> Cell<dim> cell_of_side_10() {
  Cell<dim> cell;
  cell.length = Vec<dim>::Constant(10.0);
  return cell;
}

/// Grains 4 (radius 1) and 7 (radius 0.8) along x, `ds` apart in cell_of_side_10's fractional
/// coordinates (ds = 0.18: just touching; 0.16: an overlap of 0.2).
template <int dim> ParticleStore<dim> grains_4_and_7(double ds) {
  ParticleStore<dim> p;
  Vec<dim> s = Vec<dim>::Constant(0.5);
  p.add_owned(grain<dim>(4, s, 1.0));
  s[0] += ds;
  p.add_owned(grain<dim>(7, s, 0.8));
  return p;
}

template <class T> class GrainStress : public ::testing::Test {};
using Dims = ::testing::Types<std::integral_constant<int, 2>, std::integral_constant<int, 3>>;
TYPED_TEST_SUITE(GrainStress, Dims);

// Two grains along x at distance d = 1.8 (radii 1 and 0.8, just touching), pushed apart by
// N = 2: each carries sigma_xx = N d / (2 V_g), every other component 0.
TYPED_TEST(GrainStress, TwoGrainsPressedTogether) {
  constexpr int dim = TypeParam::value;
  const Cell<dim> cell = cell_of_side_10<dim>();
  const ParticleStore<dim> p = grains_4_and_7<dim>(0.18);
  ContactStore<dim> c;
  ContactState<dim> st;
  st.normal_force = 2.0;
  c.insert(ContactKey::of(4, 7), st);
  const auto f = contact_network(cell, p, c, linear_law<dim>());
  const double radius[2] = {1.0, 0.8};
  for (std::size_t g = 0; g < 2; ++g) {
    const double expected = 2.0 * 1.8 / (2 * grain_volume<dim>(radius[g]));
    for (int a = 0; a < dim; ++a)
      for (int b = 0; b < dim; ++b)
        EXPECT_NEAR(component(f, g, a, b), a == 0 && b == 0 ? expected : 0.0, 1e-14 * expected)
            << "grain " << g << " component " << a << b;
    EXPECT_NEAR(f.mean_stress[g], expected / dim, 1e-14 * expected);
  }
}

// Triangular lattice of unit spacing (grains of radius 1/2, touching), every contact pushing
// with N = 1: sum over the 6 neighbours of n (x) n = 3 I, so sigma = (1/V) 6 (1/2) N d n(x)n
// = 3/(2V) I on every grain, V = pi/4.
TEST(GrainStress2D, TriangularLatticeIsIsotropic) {
  Cell<2> cell;
  const auto s = test::triangular_lattice(4, 3, cell);
  ParticleStore<2> p;
  for (std::size_t i = 0; i < s.size(); ++i)
    p.add_owned(grain<2>(GlobalId(i), s[i], 0.5));
  ContactStore<2> c;
  ContactState<2> st;
  st.normal_force = 1.0;
  for (std::size_t i = 0; i < s.size(); ++i)
    for (std::size_t j = i + 1; j < s.size(); ++j)
      if (std::abs(cell.min_image(s[i], s[j]).norm() - 1.0) < 1e-9)
        c.insert(ContactKey::of(GlobalId(i), GlobalId(j)), st);
  ASSERT_EQ(c.size(), 3 * s.size()); // 6 contacts per grain
  const auto f = contact_network(cell, p, c, linear_law<2>());
  const double expected = 3.0 / (2.0 * std::numbers::pi / 4.0);
  for (std::size_t g = 0; g < s.size(); ++g) {
    EXPECT_NEAR(component(f, g, 0, 0), expected, 1e-12);
    EXPECT_NEAR(component(f, g, 1, 1), expected, 1e-12);
    EXPECT_NEAR(component(f, g, 0, 1), 0.0, 1e-12);
    EXPECT_NEAR(component(f, g, 1, 0), 0.0, 1e-12);
  }
}

// Random grains with random normal and tangential forces (not in equilibrium, contacts across
// the boundary): the sum of V_g sigma_g is the virial sum_c f (x) r_12 component by
// component, and each trace over dim is mean_stress. Reversing T would change the sum: the
// check sees which end the tangential force acts on.
TYPED_TEST(GrainStress, SumsToTheCellVirialAndTracesToMeanStress) {
  constexpr int dim = TypeParam::value;
  std::mt19937_64 rng(29);
  const RandomContacts<dim> rc(rng, true, false);
  const auto& p = rc.p;
  const auto& c = rc.c;
  const int n = rc.n;
  ASSERT_GT(c.size(), 20u);
  const auto f = contact_network(rc.cell, p, c, linear_law<dim>());
  Eigen::Matrix<double, dim, dim> virial = Eigen::Matrix<double, dim, dim>::Zero();
  for (std::size_t k = 0; k < c.size(); ++k) {
    const auto [on_second, r] = rc.force_and_branch(k);
    virial += on_second * r.transpose();
  }
  Eigen::Matrix<double, dim, dim> sum = Eigen::Matrix<double, dim, dim>::Zero();
  for (std::size_t g = 0; g < std::size_t(n); ++g) {
    const double v = grain_volume<dim>(p.radius[g]);
    double trace = 0;
    for (int a = 0; a < dim; ++a) {
      trace += component(f, g, a, a);
      for (int b = 0; b < dim; ++b)
        sum(a, b) += v * component(f, g, a, b);
    }
    EXPECT_NEAR(trace / dim, f.mean_stress[g], 1e-12 * (1 + std::abs(f.mean_stress[g])));
  }
  const double scale = virial.cwiseAbs().maxCoeff();
  ASSERT_GT(scale, 0);
  EXPECT_GT((virial - virial.transpose()).cwiseAbs().maxCoeff(), 1e-3 * scale)
      << "tangential forces make the virial non-symmetric: the components are told apart";
  for (int a = 0; a < dim; ++a)
    for (int b = 0; b < dim; ++b)
      EXPECT_NEAR(sum(a, b), virial(a, b), 1e-12 * scale) << "component " << a << b;
}

// The net moment (analysis/contact_network.h) on a closed form: grains 4 and 7 along x
// (radii 1 and 0.8, overlap h = 0.2), N = 2, T = 0.5 along y on 7, and a rolling rotation
// dtheta = 0.1 about z with K_r = 3: the force acts at the middle of the overlap, at 0.9 and
// 0.7 from the centres, so M_7 = -0.7 x 0.5 - K_r dtheta = -0.65 about z and M_4 = -0.9 x 0.5
// + K_r dtheta = -0.15 (3D: only the z component). T along -y flips the lever-arm part only.
TYPED_TEST(GrainStress, NetMomentOfTwoGrains) {
  constexpr int dim = TypeParam::value;
  const Cell<dim> cell = cell_of_side_10<dim>();
  const ParticleStore<dim> p = grains_4_and_7<dim>(0.16);
  const auto law = linear_law<dim>(3.0);
  for (const double sign : {1.0, -1.0}) {
    ContactStore<dim> c;
    ContactState<dim> st;
    st.normal_force = 2.0;
    st.tangential_force[1] = 0.5 * sign;
    st.rolling[rot_dim<dim> - 1] = 0.1; // about z
    c.insert(ContactKey::of(4, 7), st);
    const auto f = contact_network(cell, p, c, law);
    const double expected[2] = {-0.9 * 0.5 * sign + 0.3, -0.7 * 0.5 * sign - 0.3};
    for (std::size_t g = 0; g < 2; ++g)
      for (int a = 0; a < rot_dim<dim>; ++a)
        EXPECT_NEAR(f.net_moment[std::size_t(a)][g], a == rot_dim<dim> - 1 ? expected[g] : 0.0,
                    1e-14)
            << "grain " << g << " component " << a << " sign " << sign;
    // The net force: -f on 4, f on 7.
    EXPECT_NEAR(f.net_force[1][1], 0.5 * sign, 1e-14);
    EXPECT_NEAR(f.net_force[0][0], -2.0, 1e-14);
  }
}

// Random grains, forces and rolling rotations across the periodic boundary: the rolling
// moments cancel pairwise and sum_g net_moment_g = -sum_c r_12 x f (f on `second`), the
// antisymmetric part of the contact virial; without tangential forces every moment is 0.
TYPED_TEST(GrainStress, NetMomentsSumToTheVirialsAntisymmetricPart) {
  constexpr int dim = TypeParam::value;
  std::mt19937_64 rng(31);
  for (const bool tangential : {true, false}) {
    const RandomContacts<dim> rc(rng, tangential, tangential);
    const int n = rc.n;
    ASSERT_GT(rc.c.size(), 20u);
    const auto f = contact_network(rc.cell, rc.p, rc.c, linear_law<dim>(2.0));
    RotVec<dim> expected = RotVec<dim>::Zero();
    for (std::size_t k = 0; k < rc.c.size(); ++k) {
      const auto [on_second, r] = rc.force_and_branch(k);
      expected -= moment<dim>(r, on_second);
    }
    RotVec<dim> sum = RotVec<dim>::Zero();
    double largest = 0;
    for (std::size_t g = 0; g < std::size_t(n); ++g)
      for (int a = 0; a < rot_dim<dim>; ++a) {
        sum[a] += f.net_moment[std::size_t(a)][g];
        largest = std::max(largest, std::abs(f.net_moment[std::size_t(a)][g]));
      }
    if (tangential) {
      ASSERT_GT(largest, 0.1);
      for (int a = 0; a < rot_dim<dim>; ++a)
        EXPECT_NEAR(sum[a], expected[a], 1e-12 * largest * n) << "component " << a;
    } else {
      EXPECT_LT(largest, 1e-14) << "central forces have no moment about the centres";
    }
  }
}

} // namespace
} // namespace granpack
