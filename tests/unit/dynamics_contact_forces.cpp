// The force loop's batched path (ContactForceLoop<3>::compute for the [AR] law) against a plain
// reference: every pair of a loose, random cloud of spheres evaluated with the scalar law
// ContactLaw<3>::force, its history kept in a map and forgotten when the pair separates. Over
// steps in which contacts form and open, the forces, torques, contact count and stored
// histories agree to rounding: the loop skips the listed pairs that do not touch without
// losing a contact or keeping a stale history.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <vector>

#include "granpack/contact/contact_law_params.h"
#include "granpack/dynamics/contact_forces.h"

using namespace granpack;

namespace {

constexpr double kRho = 2500;

struct Reference {
  std::vector<Vec<3>> force, torque;
  long contacts = 0;
};

/// The scalar law over every pair (i, j), id[i] < id[j], of the owned grains (no ghosts: the
/// cloud sits in the middle of a large cell), histories in `history`.
Reference reference_forces(const System<3>& sys, const ContactLaw<3>& law, double dt,
                           std::map<ContactKey, ContactState<3>>& history) {
  const auto& p = sys.particles;
  Reference ref;
  ref.force.assign(p.size(), Vec<3>::Zero());
  ref.torque.assign(p.size(), Vec<3>::Zero());
  for (std::size_t i = 0; i < p.size(); ++i)
    for (std::size_t j = 0; j < p.size(); ++j) {
      if (p.id[i] >= p.id[j])
        continue;
      const Vec<3> ds = p.position[j] - p.position[i];
      const Vec<3> r = sys.cell.length.cwiseProduct(ds);
      const ContactKey key{p.id[i], p.id[j]};
      const double reach = p.radius[i] + p.radius[j];
      if (r.squaredNorm() >= reach * reach) {
        history.erase(key);
        continue;
      }
      const auto g = make_pair_geometry<3>(p.radius[i], p.radius[j], p.mass[i], p.mass[j], r);
      ContactKinematics<3> kin;
      kin.v_i = p.velocity[i];
      kin.v_j = p.velocity[j] + sys.cell.rate.cwiseProduct(ds);
      kin.w_i = p.angular_velocity[i];
      kin.w_j = p.angular_velocity[j];
      const ContactForces<3> f = law.force(g, kin, history[key], dt);
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

double max_norm(const std::vector<Vec<3>>& v) {
  double m = 0;
  for (const auto& x : v)
    m = std::max(m, x.norm());
  return m;
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

  // 800 spheres of radius 0.4-0.6 mm placed at random (overlaps included) in a 14 mm cube at
  // the middle of a 40 mm cell: solid fraction about 0.15, most listed pairs apart.
  std::mt19937_64 rng(20261206);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  System<3> sys;
  sys.cell.length = Vec<3>::Constant(40e-3);
  sys.cell.rate = Vec<3>(-1e-3, 2e-3, 0.0); // the affine velocity is part of v_ij
  for (int g = 0; g < 800; ++g) {
    Particle<3> q;
    q.id = 5 * ((g * 337) % 800) + 3; // ids in no particular order
    q.radius = 0.4e-3 + 0.2e-3 * u(rng);
    q.mass = HomogeneousGrain<3>::mass(kRho, 2 * q.radius);
    q.inertia = HomogeneousGrain<3>::inertia(q.mass, 2 * q.radius);
    for (int a = 0; a < 3; ++a) {
      q.position[a] = 0.325 + 0.35 * u(rng);
      q.velocity[a] = 2.0 * (u(rng) - 0.5);
      q.angular_velocity[a] = 200.0 * (u(rng) - 0.5);
    }
    sys.particles.add_owned(q);
  }

  const double dt = 2e-6; // up to 2 um per step: over 30 steps, 60 um < skin / 2
  VerletList<3> list;
  list.build(sys.particles, sys.cell, NeighborParams{0.2e-3, 0.0});
  ContactForceLoop<3> loop;
  loop.bind(sys.particles, list, sys.contacts);
  std::map<ContactKey, ContactState<3>> history;
  long formed = 0, opened = 0, listed_apart = 0;
  for (int step = 0; step < 30; ++step) {
    const std::map<ContactKey, ContactState<3>> before = history;
    const ForceSums<3> sums = loop.compute(sys, list, law, dt);
    const Reference ref = reference_forces(sys, law, dt, history);
    for (const auto& [key, st] : history)
      formed += before.count(key) == 0 ? 1 : 0;
    for (const auto& [key, st] : before)
      opened += history.count(key) == 0 ? 1 : 0;
    listed_apart += static_cast<long>(list.n_pairs()) - ref.contacts;

    ASSERT_EQ(sums.interacting, ref.contacts) << "step " << step;
    const double f_scale = max_norm(ref.force), t_scale = max_norm(ref.torque);
    for (std::size_t i = 0; i < sys.particles.size(); ++i) {
      ASSERT_LE((sys.particles.force[i] - ref.force[i]).norm(), 1e-10 * f_scale)
          << "step " << step << ", grain " << i;
      ASSERT_LE((sys.particles.torque[i] - ref.torque[i]).norm(), 1e-10 * t_scale)
          << "step " << step << ", grain " << i;
    }
    // The live histories are the reference's (an opened contact is reset to age 0).
    long live = 0;
    for (std::size_t k = 0; k < sys.contacts.size(); ++k) {
      const ContactState<3>& st = sys.contacts.state(k);
      if (st.age == 0)
        continue;
      ++live;
      const auto it = history.find(sys.contacts.key(k));
      ASSERT_NE(it, history.end()) << "step " << step;
      EXPECT_NEAR(st.normal_force, it->second.normal_force,
                  1e-10 * std::abs(it->second.normal_force) + 1e-300);
      EXPECT_LE((st.tangential_force - it->second.tangential_force).norm(),
                1e-9 * it->second.tangential_force.norm() + 1e-300);
    }
    EXPECT_EQ(live, ref.contacts) << "step " << step;

    // Drift (no forces applied: the cloud stays loose); the list stays valid.
    for (std::size_t i = 0; i < sys.particles.size(); ++i)
      sys.particles.position[i] += (dt * sys.particles.velocity[i]).cwiseQuotient(sys.cell.length);
    ASSERT_FALSE(list.needs_rebuild(sys.particles, sys.cell));
  }
  // The case covers what it claims: contacts formed and opened, and most listed pairs apart.
  EXPECT_GT(formed, 10);
  EXPECT_GT(opened, 10);
  EXPECT_GT(listed_apart, 30 * 100);
}
