// Ghost exchange and migration against brute force, and the shared-memory halo against the
// message one bit for bit, on whatever rank count ctest gives.
#include <gtest/gtest.h>
#include <mpi.h>
#include <sys/resource.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <tuple>

#include "granpack/comm/decomposition.h"
#include "granpack/comm/halo.h"
#include "granpack/comm/migration.h"
#include "granpack/comm/reduce.h"
#include "granpack/comm/shared_window.h"
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

namespace {

/// Differences between two stores, bit for bit (-0.0 differs from 0.0; a NaN from itself
/// only if its bits do): "" if none, else how many and the first.
template <int dim>
std::string bit_differences(const ParticleStore<dim>& a, const ParticleStore<dim>& b) {
  if (a.size() != b.size() || a.n_owned() != b.n_owned())
    return "sizes differ: " + std::to_string(a.size()) + " and " + std::to_string(b.size());
  std::size_t count = 0;
  std::ostringstream first;
  auto compare = [&](std::size_t i, const char* what, int k, double x, double y) {
    if (std::bit_cast<std::uint64_t>(x) == std::bit_cast<std::uint64_t>(y))
      return;
    if (count++ == 0)
      first << what << "[" << k << "] of particle " << i << " (id " << a.id[i] << "): " << x
            << " and " << y;
  };
  for (std::size_t i = 0; i < a.size(); ++i) {
    compare(i, "id", 0, double(a.id[i]), double(b.id[i]));
    for (int k = 0; k < dim; ++k) {
      compare(i, "position", k, a.position[i][k], b.position[i][k]);
      compare(i, "velocity", k, a.velocity[i][k], b.velocity[i][k]);
      compare(i, "force", k, a.force[i][k], b.force[i][k]);
    }
    for (int k = 0; k < rot_dim<dim>; ++k) {
      compare(i, "angular velocity", k, a.angular_velocity[i][k], b.angular_velocity[i][k]);
      compare(i, "torque", k, a.torque[i][k], b.torque[i][k]);
    }
  }
  return count == 0 ? std::string() : std::to_string(count) + " differ, first " + first.str();
}

/// A value of grain `id` in exchange `round`, component k: new at every round, the same on any
/// rank count, of either sign and of varied magnitude (sums of them round differently if their
/// order changes).
double value_of(GlobalId id, int round, int k) {
  return std::sin(0.37 * double(id) + 1.1 * round + 0.13 * k) * std::exp(0.5 * std::cos(k + id));
}

/// The shared-memory halo (HaloTransport::shared_memory) against the message halo on the same
/// grains and the same grid `dims`: after every borders(), forward() and reverse() of several
/// exchanges (both parities of the double buffer, several times), every position, velocity,
/// angular velocity, force and torque of every owned grain and ghost is the same bit for bit.
/// The ghost layer first widens (the ghosts outgrow the window's headroom: it is reallocated)
/// and then narrows (it fits: no reallocation). On one rank both are the message path's
/// in-place copies; on more, all on one node, the window carries every non-self swap.
template <int dim>
void expect_shared_memory_halo_equals_messages(const std::array<int, dim>& dims) {
  const auto all = random_grains<dim>(dim == 3 ? 3000 : 1500, 17);
  Decomposition<dim> d(MPI_COMM_WORLD, dims);
  ParticleStore<dim> pm, ps; // through messages, through shared memory
  for (const auto& q : all)
    if (d.owns(q.position)) {
      pm.add_owned(q);
      ps.add_owned(q);
    }
  Halo<dim> hm(HaloTransport::messages), hs(HaloTransport::shared_memory);
  const bool shared = d.size() > 1 && ranks_share_one_node(MPI_COMM_WORLD);
  int round = 0, allocations = 0;
  for (const double width : {0.05, 0.2, 0.1}) {
    const Vec<dim> w = Vec<dim>::Constant(width);
    hm.borders(pm, d, w);
    hs.borders(ps, d, w);
    EXPECT_EQ(hs.through_shared_memory(), shared);
    EXPECT_FALSE(hm.through_shared_memory());
    if (shared) {
      if (width == 0.05)
        EXPECT_EQ(hs.window_allocations(), 1) << "the first borders() allocates";
      else if (width == 0.2)
        EXPECT_EQ(hs.window_allocations(), allocations + 1) << "4x the ghosts: reallocated";
      else
        EXPECT_EQ(hs.window_allocations(), allocations) << "fewer ghosts: the room suffices";
    }
    allocations = hs.window_allocations();
    EXPECT_EQ(bit_differences(pm, ps), "") << "after borders(), width " << width;
    for (int k = 0; k < 5; ++k, ++round) {
      for (ParticleStore<dim>* p : {&pm, &ps}) {
        for (std::size_t i = 0; i < p->n_owned(); ++i) {
          const GlobalId id = p->id[i];
          for (int a = 0; a < dim; ++a) {
            p->position[i][a] = all[(id - 1000) / 3].position[a] + 1e-4 * value_of(id, round, a);
            p->velocity[i][a] = value_of(id, round, dim + a);
          }
          for (int a = 0; a < rot_dim<dim>; ++a)
            p->angular_velocity[i][a] = value_of(id, round, 2 * dim + a);
        }
      }
      hm.forward(pm, d);
      hs.forward(ps, d);
      EXPECT_EQ(bit_differences(pm, ps), "") << "forward, width " << width << ", round " << round;
      // Forces on owners and ghosts alike (the owners' own add to what the ghosts bring),
      // a ghost's by its index too: the images of one grain carry different forces.
      for (ParticleStore<dim>* p : {&pm, &ps}) {
        for (std::size_t i = 0; i < p->size(); ++i) {
          for (int a = 0; a < dim; ++a)
            p->force[i][a] = value_of(p->id[i] + 7 * i, round, 3 * dim + a);
          for (int a = 0; a < rot_dim<dim>; ++a)
            p->torque[i][a] = value_of(p->id[i] + 7 * i, round, 4 * dim + a);
        }
      }
      hm.reverse(pm, d);
      hs.reverse(ps, d);
      EXPECT_EQ(bit_differences(pm, ps), "") << "reverse, width " << width << ", round " << round;
    }
  }
}

/// The grid that puts every rank along the last axis (1 x ... x size): the axes before it are
/// one rank wide, so the last axis sends periodic images (made in place) of the grains.
template <int dim> std::array<int, dim> all_along_the_last_axis() {
  std::array<int, dim> dims;
  dims.fill(1);
  MPI_Comm_size(MPI_COMM_WORLD, &dims[dim - 1]);
  return dims;
}

/// The grid the engine would choose for a cubic cell (2 ranks: 2x1x1, 3: 3x1x1, 4: 2x2x1).
template <int dim> std::array<int, dim> default_grid() {
  Decomposition<dim> d(MPI_COMM_WORLD, Vec<dim>::Ones());
  return d.dims();
}

} // namespace

// On 2 ranks (2x1x1, and 1x1x2 below) both neighbours along the cut axis are the same rank,
// the case where one rank reads both slots of the other; on 3 ranks (3x1x1) they differ; on 4
// (2x2x1) two axes use the window, the second sending the first's ghosts on. Each grid crosses
// the periodic boundary (shifted images) along every axis.
TEST(HaloSharedMemory, EqualsMessagesBitForBit2D) {
  expect_shared_memory_halo_equals_messages<2>(default_grid<2>());
}
TEST(HaloSharedMemory, EqualsMessagesBitForBit3D) {
  expect_shared_memory_halo_equals_messages<3>(default_grid<3>());
}
TEST(HaloSharedMemory, EqualsMessagesBitForBitWithImagesSentOn2D) {
  expect_shared_memory_halo_equals_messages<2>(all_along_the_last_axis<2>());
}
TEST(HaloSharedMemory, EqualsMessagesBitForBitWithImagesSentOn3D) {
  expect_shared_memory_halo_equals_messages<3>(all_along_the_last_axis<3>());
}

// A file size limit (ulimit -f) that the window's backing file would pass: Open MPI would fail
// inside MPI_Win_allocate_shared and abort the job. On rank 0 alone (any rank's limit must
// turn every rank to messages, or the ranks would disagree on the transport) the limit is set
// to 4 kB: the halo allocates no window, on any rank, and carries the same values by messages.
TEST(HaloSharedMemory, AFileSizeLimitBelowTheWindowFallsBackToMessagesOnEveryRank) {
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  rlimit saved{};
  ASSERT_EQ(getrlimit(RLIMIT_FSIZE, &saved), 0);
  if (rank == 0) {
    rlimit small = saved;
    small.rlim_cur = 4096;
    ASSERT_EQ(setrlimit(RLIMIT_FSIZE, &small), 0);
    EXPECT_EQ(file_size_limit(), 4096u);
  }
  const auto all = random_grains<3>(3000, 17);
  Decomposition<3> d(MPI_COMM_WORLD, default_grid<3>());
  ParticleStore<3> pm, ps;
  for (const auto& q : all)
    if (d.owns(q.position)) {
      pm.add_owned(q);
      ps.add_owned(q);
    }
  Halo<3> hm(HaloTransport::messages), hs(HaloTransport::shared_memory);
  for (const double width : {0.05, 0.2}) {
    hm.borders(pm, d, Vec<3>::Constant(width));
    hs.borders(ps, d, Vec<3>::Constant(width));
    EXPECT_FALSE(hs.through_shared_memory()) << "width " << width;
    EXPECT_EQ(hs.window_allocations(), 0);
    for (ParticleStore<3>* p : {&pm, &ps})
      for (std::size_t i = 0; i < p->size(); ++i)
        for (int a = 0; a < 3; ++a)
          p->force[i][a] = value_of(p->id[i] + 7 * i, 1, a);
    hm.forward(pm, d);
    hs.forward(ps, d);
    hm.reverse(pm, d);
    hs.reverse(ps, d);
    EXPECT_EQ(bit_differences(pm, ps), "") << "width " << width;
  }
  if (rank == 0)
    ASSERT_EQ(setrlimit(RLIMIT_FSIZE, &saved), 0);
}

// An error on every rank while a shared-memory halo is alive (a collective error, as the
// engine's): unwinding leaves its window to MPI_Finalize instead of a collective free (which
// would hang if the error were one rank's alone), and the ranks carry on: a new halo works.
TEST(HaloSharedMemory, ACollectiveErrorWhileItIsAliveLetsTheRanksCarryOn) {
  const auto all = random_grains<3>(500, 5);
  Decomposition<3> d(MPI_COMM_WORLD, Vec<3>::Ones());
  auto owned = [&] {
    ParticleStore<3> p;
    for (const auto& q : all)
      if (d.owns(q.position))
        p.add_owned(q);
    return p;
  };
  ParticleStore<3> p = owned();
  try {
    Halo<3> halo(HaloTransport::shared_memory);
    halo.borders(p, d, Vec<3>::Constant(0.1));
    halo.forward(p, d);
    throw InputError("every rank fails here");
  } catch (const InputError&) {
  }
  EXPECT_EQ(global_sum(MPI_COMM_WORLD, std::int64_t(1)), d.size());
  ParticleStore<3> pm = owned(), ps = owned();
  Halo<3> hm(HaloTransport::messages), hs(HaloTransport::shared_memory);
  hm.borders(pm, d, Vec<3>::Constant(0.1));
  hs.borders(ps, d, Vec<3>::Constant(0.1));
  hm.forward(pm, d);
  hs.forward(ps, d);
  EXPECT_EQ(bit_differences(pm, ps), "");
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
