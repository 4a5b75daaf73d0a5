// Ghost exchange and migration against brute force, on whatever rank count ctest gives.
#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>
#include <map>
#include <random>
#include <set>
#include <tuple>

#include "granpack/comm/decomposition.h"
#include "granpack/comm/halo.h"
#include "granpack/comm/migration.h"
#include "granpack/comm/reduce.h"
#include "granpack/core/cut_planes.h"
#include "granpack/core/error.h"

using namespace granpack;

namespace {

template <int dim> std::vector<Particle<dim>> random_grains(int n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Particle<dim>> all(n);
  for (int k = 0; k < n; ++k) {
    all[k].id = 1000 + 3 * k; // ids need not be contiguous
    all[k].radius = 0.01 + 0.01 * u(rng);
    all[k].mass = 1.0 + u(rng);
    for (int a = 0; a < dim; ++a) {
      all[k].position[a] = u(rng);
      all[k].velocity[a] = u(rng) - 0.5;
    }
  }
  return all;
}

/// Every periodic image (shift in {-1,0,1}^dim) of every grain inside the box expanded by w,
/// except the owned grains themselves: what the ghost layer must contain.
template <int dim>
std::multiset<std::pair<GlobalId, std::vector<int>>>
expected_ghosts(const std::vector<Particle<dim>>& all, const Decomposition<dim>& d,
                const Vec<dim>& w) {
  std::multiset<std::pair<GlobalId, std::vector<int>>> out;
  int nshift = 1;
  for (int a = 0; a < dim; ++a)
    nshift *= 3;
  for (const auto& q : all) {
    for (int code = 0; code < nshift; ++code) {
      std::vector<int> sh(dim);
      int c = code;
      bool inside = true, zero = true;
      for (int a = 0; a < dim; ++a) {
        sh[a] = c % 3 - 1;
        c /= 3;
        double x = q.position[a] + sh[a];
        inside = inside && x >= d.lo()[a] - w[a] && x < d.hi()[a] + w[a];
        zero = zero && sh[a] == 0;
      }
      if (!inside)
        continue;
      if (zero && d.owns(q.position))
        continue;
      out.insert({q.id, sh});
    }
  }
  return out;
}

/// Uneven cut planes, as the load balancer makes them: slab k of an axis cut in m ends at
/// ((k+1)/m)^1.5 (narrow slabs near 0, wide ones near 1).
template <int dim> void cut_unevenly(Decomposition<dim>& d) {
  std::array<std::vector<double>, dim> cuts;
  for (int a = 0; a < dim; ++a) {
    const int m = d.dims()[a];
    for (int k = 0; k <= m; ++k)
      cuts[a].push_back(k == m ? 1.0 : std::pow(double(k) / m, 1.5));
  }
  d.set_cuts(cuts);
}

template <int dim> void check_halo(double width, bool uneven = false) {
  auto all = random_grains<dim>(dim == 3 ? 3000 : 1500, 42);
  Decomposition<dim> d(MPI_COMM_WORLD, Vec<dim>::Ones());
  if (uneven)
    cut_unevenly(d);
  ParticleStore<dim> p;
  std::map<GlobalId, Vec<dim>> pos_of;
  for (const auto& q : all) {
    pos_of[q.id] = q.position;
    if (d.owns(q.position))
      p.add_owned(q);
  }
  Vec<dim> w = Vec<dim>::Constant(width);
  Halo<dim> halo;
  halo.borders(p, d, w);

  std::multiset<std::pair<GlobalId, std::vector<int>>> got;
  for (std::size_t g = p.n_owned(); g < p.size(); ++g) {
    std::vector<int> sh(dim);
    for (int a = 0; a < dim; ++a)
      sh[a] = static_cast<int>(std::lround(p.position[g][a] - pos_of[p.id[g]][a]));
    got.insert({p.id[g], sh});
  }
  EXPECT_EQ(got, expected_ghosts(all, d, w));

  // forward: owners move, ghosts follow with their image shift
  for (std::size_t i = 0; i < p.n_owned(); ++i) {
    p.position[i] += Vec<dim>::Constant(1e-3);
    p.velocity[i] = Vec<dim>::Constant(double(p.id[i]));
  }
  halo.forward(p, d);
  for (std::size_t g = p.n_owned(); g < p.size(); ++g) {
    for (int a = 0; a < dim; ++a) {
      double frac = p.position[g][a] - std::floor(p.position[g][a]);
      EXPECT_NEAR(frac, pos_of[p.id[g]][a] + 1e-3 - std::floor(pos_of[p.id[g]][a] + 1e-3), 1e-12);
    }
    EXPECT_EQ(p.velocity[g][0], double(p.id[g]));
  }

  // reverse: each ghost carries force 1; each owner receives one per copy of itself
  p.clear_forces();
  for (std::size_t g = p.n_owned(); g < p.size(); ++g)
    p.force[g] = Vec<dim>::Ones();
  // copies of each grain over all ranks, indexed like `all`
  std::map<GlobalId, std::size_t> index_of;
  for (std::size_t k = 0; k < all.size(); ++k)
    index_of[all[k].id] = k;
  std::vector<double> copies(all.size(), 0.0), total(all.size(), 0.0);
  for (std::size_t g = p.n_owned(); g < p.size(); ++g)
    copies[index_of[p.id[g]]] += 1.0;
  MPI_Allreduce(copies.data(), total.data(), int(all.size()), MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  halo.reverse(p, d);
  for (std::size_t g = p.n_owned(); g < p.size(); ++g)
    EXPECT_EQ(p.force[g][0], 0.0);
  for (std::size_t i = 0; i < p.n_owned(); ++i)
    EXPECT_EQ(p.force[i][0], total[index_of[p.id[i]]]) << "grain " << p.id[i];
}

} // namespace

TEST(Halo, GhostLayerEqualsBruteForceImages2D) {
  check_halo<2>(0.08);
}
TEST(Halo, GhostLayerEqualsBruteForceImages3D) {
  check_halo<3>(0.08);
}
TEST(Halo, WideLayerStillExact3D) {
  check_halo<3>(0.3);
}
TEST(Halo, UnevenSubBoxesStillExact2D) {
  check_halo<2>(0.08, true);
}
TEST(Halo, UnevenSubBoxesStillExact3D) {
  check_halo<3>(0.08, true);
}

TEST(Decomposition, UnevenCutsGiveEveryPointOneOwnerInsideItsBox) {
  Decomposition<3> d(MPI_COMM_WORLD, Vec<3>::Ones());
  cut_unevenly(d);
  EXPECT_EQ(d.uniform(), d.size() == 1);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int mine = 0;
  const int n = 2000;
  for (int k = 0; k < n; ++k) {
    Vec<3> s(u(rng), u(rng), u(rng));
    if (k < 3) // the planes themselves belong to the slab above them
      s = Vec<3>(d.cuts(0)[d.dims()[0] - 1], d.cuts(1)[d.dims()[1] - 1], 0.0);
    const bool inside = (s.array() >= d.lo().array()).all() && (s.array() < d.hi().array()).all();
    EXPECT_EQ(d.owns(s), inside) << s.transpose();
    mine += d.owns(s) ? 1 : 0;
  }
  EXPECT_EQ(global_sum(MPI_COMM_WORLD, std::int64_t(mine)), n) << "every point has one owner";
}

TEST(Halo, SubBoxNarrowerThanTheGhostLayerIsRefusedOnEveryRank) {
  Decomposition<3> d(MPI_COMM_WORLD, Vec<3>::Ones());
  if (d.size() == 1)
    GTEST_SKIP() << "one rank: no cut planes to move";
  // The first slab of the most-cut axis is 0.05 of the cell: a ghost layer of 0.08 needs grains
  // from beyond the nearest sub-domain. Every rank must refuse (not only the narrow one).
  int axis = 0;
  for (int a = 1; a < 3; ++a)
    if (d.dims()[a] > d.dims()[axis])
      axis = a;
  std::array<std::vector<double>, 3> cuts{uniform_cuts(d.dims()[0]), uniform_cuts(d.dims()[1]),
                                          uniform_cuts(d.dims()[2])};
  cuts[axis][1] = 0.05;
  d.set_cuts(cuts);
  EXPECT_DOUBLE_EQ(d.narrowest(axis), 0.05);
  ParticleStore<3> p;
  Halo<3> halo;
  try {
    halo.borders(p, d, Vec<3>::Constant(0.08));
    ADD_FAILURE() << "a ghost layer wider than a sub-box was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("narrowest"), std::string::npos) << e.what();
  }
}

TEST(Migration, GrainsAndTheirContactsReachTheirOwners) {
  constexpr int dim = 3;
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  auto all = random_grains<dim>(2000, 7);
  Decomposition<dim> d(MPI_COMM_WORLD, Vec<dim>::Ones());
  System<dim> sys;
  // Deliberately wrong initial split: round robin by index, positions slightly outside [0,1).
  for (std::size_t k = 0; k < all.size(); ++k) {
    if (int(k % size) != rank)
      continue;
    auto q = all[k];
    if (k % 5 == 0)
      q.position[0] -= 1.0; // must be wrapped back
    sys.particles.add_owned(q);
    ContactState<dim> s;
    s.normal_force = double(q.id);
    s.age = 17;
    sys.contacts.insert(ContactKey::of(q.id, q.id + 1), s); // owned by q (smaller id)
  }
  migrate(sys, d);
  EXPECT_EQ(global_sum(MPI_COMM_WORLD, std::int64_t(sys.particles.n_owned())), 2000);
  EXPECT_EQ(global_sum(MPI_COMM_WORLD, std::int64_t(sys.contacts.size())), 2000);
  std::set<GlobalId> mine;
  for (std::size_t i = 0; i < sys.particles.n_owned(); ++i) {
    EXPECT_TRUE(d.owns(sys.particles.position[i]));
    mine.insert(sys.particles.id[i]);
  }
  for (std::size_t k = 0; k < sys.contacts.size(); ++k) {
    EXPECT_TRUE(mine.count(sys.contacts.key(k).first)) << "contact left behind its grain";
    EXPECT_EQ(sys.contacts.state(k).normal_force, double(sys.contacts.key(k).first));
    EXPECT_EQ(sys.contacts.state(k).age, 17);
  }
}
