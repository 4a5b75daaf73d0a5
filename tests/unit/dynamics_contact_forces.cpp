// The force loop's batched paths (ContactForceLoop<3>::compute for the [AR] law, and
// ContactForceLoop<2>::compute for [GRC]'s 2D law with cohesion and rolling resistance) against
// a plain reference: every pair of a loose, random cloud of grains evaluated with the scalar law
// ContactLaw<dim>::force, its history kept in a map and forgotten when the pair leaves the
// law's range. Over steps in which contacts form and open (and, in 2D, slide, roll to their
// threshold and pass through the cohesion's range), the forces, torques, contact count and
// stored histories agree to rounding: the loop skips the listed pairs out of range without
// losing a contact or keeping a stale history.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <vector>

#include "granpack/contact/contact_law_params.h"
#include "granpack/dynamics/contact_forces.h"

using namespace granpack;

namespace {

constexpr double kRho = 2500;

template <int dim> struct Reference {
  std::vector<Vec<dim>> force;
  std::vector<RotVec<dim>> torque;
  long contacts = 0;
};

/// The scalar law over every pair (i, j), id[i] < id[j], of the owned grains (no ghosts: the
/// cloud sits in the middle of a large cell), histories in `history`.
template <int dim>
Reference<dim> reference_forces(const System<dim>& sys, const ContactLaw<dim>& law, double dt,
                                std::map<ContactKey, ContactState<dim>>& history) {
  const auto& p = sys.particles;
  Reference<dim> ref;
  ref.force.assign(p.size(), Vec<dim>::Zero());
  ref.torque.assign(p.size(), RotVec<dim>::Zero());
  for (std::size_t i = 0; i < p.size(); ++i)
    for (std::size_t j = 0; j < p.size(); ++j) {
      if (p.id[i] >= p.id[j])
        continue;
      const Vec<dim> ds = p.position[j] - p.position[i];
      const Vec<dim> r = sys.cell.length.cwiseProduct(ds);
      const ContactKey key{p.id[i], p.id[j]};
      const double reach = p.radius[i] + p.radius[j] + law.interaction_range();
      if (r.squaredNorm() >= reach * reach) {
        history.erase(key);
        continue;
      }
      const auto g = make_pair_geometry<dim>(p.radius[i], p.radius[j], p.mass[i], p.mass[j], r);
      ContactKinematics<dim> kin;
      kin.v_i = p.velocity[i];
      kin.v_j = p.velocity[j] + sys.cell.rate.cwiseProduct(ds);
      kin.w_i = p.angular_velocity[i];
      kin.w_j = p.angular_velocity[j];
      const ContactForces<dim> f = law.force(g, kin, history[key], dt);
      if (!f.active)
        continue;
      ref.force[j] += f.force_on_j;
      ref.force[i] -= f.force_on_j;
      ref.torque[i] += f.torque_i;
      ref.torque[j] += f.torque_j;
      ++ref.contacts;
    }
  return ref;
}

template <class V> double max_norm(const std::vector<V>& v) {
  double m = 0;
  for (const auto& x : v)
    m = std::max(m, x.norm());
  return m;
}

/// What a run of the cloud went through, counted on the reference's histories.
struct Seen {
  long formed = 0, opened = 0, listed_apart = 0;
  long sliding = 0, rolling_plastic = 0, distant = 0; ///< contact-steps with each flag
};

/// `steps` steps of the batched loop and of the reference on the same cloud, compared after
/// each step (the first failure ends the run); the grains drift without forces (the list stays
/// valid). Counts in `seen` what the contacts went through.
template <int dim>
void compare_with_reference(System<dim>& sys, const ContactLaw<dim>& law, double skin, double dt,
                            int steps, Seen& seen) {
  VerletList<dim> list;
  list.build(sys.particles, sys.cell, NeighborParams{skin, law.interaction_range()});
  ContactForceLoop<dim> loop;
  loop.bind(sys.particles, list, sys.contacts);
  std::map<ContactKey, ContactState<dim>> history;
  for (int step = 0; step < steps; ++step) {
    SCOPED_TRACE("step " + std::to_string(step));
    const std::map<ContactKey, ContactState<dim>> before = history;
    const ForceSums<dim> sums = loop.compute(sys, list, law, dt);
    const Reference<dim> ref = reference_forces(sys, law, dt, history);
    for (const auto& [key, st] : history) {
      seen.formed += before.count(key) == 0 ? 1 : 0;
      seen.sliding += (st.flags & kSliding) ? 1 : 0;
      seen.rolling_plastic += (st.flags & kRollingPlastic) ? 1 : 0;
      seen.distant += (st.flags & kDistant) ? 1 : 0;
    }
    for (const auto& [key, st] : before)
      seen.opened += history.count(key) == 0 ? 1 : 0;
    seen.listed_apart += static_cast<long>(list.n_pairs()) - ref.contacts;

    ASSERT_EQ(sums.interacting, ref.contacts);
    const double f_scale = max_norm(ref.force), t_scale = max_norm(ref.torque);
    for (std::size_t i = 0; i < sys.particles.size(); ++i) {
      ASSERT_LE((sys.particles.force[i] - ref.force[i]).norm(), 1e-10 * f_scale) << "grain " << i;
      ASSERT_LE((sys.particles.torque[i] - ref.torque[i]).norm(), 1e-10 * t_scale) << "grain " << i;
    }
    // The live histories are the reference's (an opened contact is reset to age 0).
    long live = 0;
    for (std::size_t k = 0; k < sys.contacts.size(); ++k) {
      const ContactState<dim>& st = sys.contacts.state(k);
      if (st.age == 0)
        continue;
      ++live;
      const auto it = history.find(sys.contacts.key(k));
      ASSERT_NE(it, history.end());
      const ContactState<dim>& want = it->second;
      EXPECT_NEAR(st.normal_force, want.normal_force, 1e-10 * std::abs(want.normal_force) + 1e-300);
      EXPECT_LE((st.tangential_force - want.tangential_force).norm(),
                1e-9 * want.tangential_force.norm() + 1e-300);
      EXPECT_LE((st.rolling - want.rolling).norm(), 1e-9 * want.rolling.norm() + 1e-300);
      EXPECT_EQ(st.flags, want.flags);
      EXPECT_EQ(st.age, want.age);
    }
    EXPECT_EQ(live, ref.contacts);

    for (std::size_t i = 0; i < sys.particles.size(); ++i)
      sys.particles.position[i] += (dt * sys.particles.velocity[i]).cwiseQuotient(sys.cell.length);
    ASSERT_FALSE(list.needs_rebuild(sys.particles, sys.cell));
  }
}

/// `count` grains of radius 0.4-0.6 mm placed at random (overlaps included) in the middle
/// `width` (scaled) of a cell of side `side`, ids in no particular order, velocities up to
/// 1 m/s per axis, spins up to 100 rad/s.
template <int dim> System<dim> random_cloud(int count, double side, double width) {
  std::mt19937_64 rng(20261206);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  System<dim> sys;
  sys.cell.length = Vec<dim>::Constant(side);
  sys.cell.rate = Vec<dim>::Zero();
  sys.cell.rate[0] = -1e-3; // the affine velocity is part of v_ij
  sys.cell.rate[1] = 2e-3;
  for (int g = 0; g < count; ++g) {
    Particle<dim> q;
    q.id = 5 * ((g * 337) % count) + 3;
    q.radius = 0.4e-3 + 0.2e-3 * u(rng);
    q.mass = HomogeneousGrain<dim>::mass(kRho, 2 * q.radius);
    q.inertia = HomogeneousGrain<dim>::inertia(q.mass, 2 * q.radius);
    for (int a = 0; a < dim; ++a) {
      q.position[a] = 0.5 * (1 - width) + width * u(rng);
      q.velocity[a] = 2.0 * (u(rng) - 0.5);
      if (a < rot_dim<dim>)
        q.angular_velocity[a] = 200.0 * (u(rng) - 0.5);
    }
    sys.particles.add_owned(q);
  }
  return sys;
}

/// compare_with_reference over 30 steps of up to 2 um with a 0.2 mm skin, and a check that the
/// case covers what it claims: contacts formed and opened, and most listed pairs apart.
template <int dim> Seen compare_over_30_steps(System<dim> sys, const ContactLaw<dim>& law) {
  Seen seen;
  compare_with_reference(sys, law, 0.2e-3, 2e-6, 30, seen);
  EXPECT_GT(seen.formed, 10);
  EXPECT_GT(seen.opened, 10);
  EXPECT_GT(seen.listed_apart, 30 * 100);
  return seen;
}

} // namespace

TEST(ContactForceLoop, BatchedLoopMatchesTheScalarLawAsContactsFormAndOpen) {
  ContactLawParams prm;
  prm.young_modulus = 70e9;
  prm.poisson_ratio = 0.3;
  prm.friction = 0.3;
  prm.damping_ratio = 0.5;
  const ContactLaw<3> law = make_contact_law<3>(prm);
  ASSERT_TRUE(HertzMindlinConstants::of(law).has_value()); // the batched path is under test

  // 800 spheres in a 14 mm cube at the middle of a 40 mm cell: solid fraction about 0.15, most
  // listed pairs apart. dt: up to 2 um per step, over 30 steps 60 um < skin / 2.
  compare_over_30_steps(random_cloud<3>(800, 40e-3, 0.35), law);
}

// [GRC]'s 2D law (linear normal force, damping, friction, cohesion of range D0, rolling
// resistance with its damping) and a Hertz 2D law with Walton's rescaling, through the 2D
// batch (DiskContactBatch) and its scatter of the histories (T, N^e, δθ, flags, age).
TEST(ContactForceLoop, Batched2dLoopMatchesTheScalarLawAsContactsFormSlideRollAndOpen) {
  ContactLawParams grc;
  grc.normal = NormalLawKind::kLinear;
  grc.k_n = 1e5;
  grc.tangential = TangentialStiffnessKind::kRatio;
  grc.k_t_ratio = 1.0;
  grc.friction = 0.5;
  grc.damping_ratio = 0.8;
  grc.cohesion_force = 1.0;
  grc.cohesion_range = 20e-6; // 10 steps of a pair receding at 1 m/s
  grc.rolling_stiffness = 1e-2;
  grc.rolling_friction = 5e-6;
  grc.rolling_damping = 0.1;
  ContactLawParams hertz;
  hertz.young_modulus = 1e8;
  hertz.poisson_ratio = 0.3;
  hertz.friction = 0.3;
  hertz.damping_ratio = 0.5;
  ContactLawParams no_tension = grc;
  no_tension.damping_tension = false;
  no_tension.friction = std::numeric_limits<double>::infinity();
  no_tension.rolling_friction = std::numeric_limits<double>::infinity();
  for (const ContactLawParams& prm : {grc, hertz, no_tension}) {
    const ContactLaw<2> law = make_contact_law<2>(prm);
    ASSERT_TRUE(DiskContactConstants::of(law).has_value()); // the batched path is under test
    // 800 disks in a 46 mm square at the middle of a 100 mm cell: area fraction about 0.3.
    const Seen seen = compare_over_30_steps(random_cloud<2>(800, 100e-3, 0.46), law);
    if (std::isfinite(prm.friction)) {
      EXPECT_GT(seen.sliding, 30);
    }
    if (prm.cohesion_force > 0) {
      EXPECT_GT(seen.distant, 30);
    }
    if (prm.rolling_stiffness > 0 && std::isfinite(prm.rolling_friction)) {
      EXPECT_GT(seen.rolling_plastic, 30);
    }
  }
}
