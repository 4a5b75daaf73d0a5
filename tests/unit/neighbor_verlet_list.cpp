// VerletList: pair sets against brute force under the ownership rule (one rank of a
// decomposition, a whole decomposition, a whole periodic system on one rank), and the rebuild
// criterion under grain moves and cell changes.
#include <gtest/gtest.h>

#include <random>
#include <set>
#include <vector>

#include "granpack/core/error.h"
#include "granpack/neighbor/verlet_list.h"
#include "neighbor_fixtures.h"

namespace granpack {
namespace {

using test::PairKey;

template <class D> class VerletListTest : public ::testing::Test {
protected:
  // A sample of ~5 neighbours per grain; L_alpha > 2 max cutoff with room for cell changes.
  static test::World<D::value> world(std::mt19937_64& rng, double skin = 0.15,
                                     double range = 0.05) {
    constexpr int dim = D::value;
    Vec<dim> length;
    std::size_t n;
    if constexpr (dim == 2) {
      length = Vec<dim>(10.0, 12.5);
      n = 420;
    } else {
      length = Vec<dim>(8.0, 9.0, 10.5);
      n = 700;
    }
    return test::make_world<dim>(rng, n, length, 0.25, 0.5, NeighborParams{skin, range});
  }
};
TYPED_TEST_SUITE(VerletListTest, test::Dims);

// Every sub-box of a decomposition lists exactly the pairs whose smaller-id grain it owns, and
// the union over the sub-boxes is the brute-force minimum-image pair set, each pair once.
TYPED_TEST(VerletListTest, DecompositionUnionEqualsBruteForceEachPairOnce) {
  constexpr int dim = TypeParam::value;
  std::mt19937_64 rng(21);
  for (const auto& [skin, range] :
       {std::pair{0.15, 0.05}, std::pair{0.0, 0.0}, std::pair{0.3, 0.2}}) {
    const auto w = TestFixture::world(rng, skin, range);
    const auto expected = test::brute_force_pairs(w, range + skin);
    ASSERT_GT(expected.size(), w.s.size() / 4); // a meaningful number of pairs
    // uneven cuts: 3 x 2 (x 2) sub-boxes, one thinner than the ghost layer
    const std::vector<std::vector<double>> cuts = {
        {0.0, 0.07, 0.6, 1.0}, {0.0, 0.45, 1.0}, {0.0, 0.3, 1.0}};
    std::set<PairKey<dim>> all;
    std::size_t n_listed = 0, n_owned = 0;
    std::array<std::size_t, dim> b{};
    while (true) {
      Vec<dim> lo, hi;
      for (int a = 0; a < dim; ++a) {
        lo[a] = cuts[a][b[a]];
        hi[a] = cuts[a][b[a] + 1];
      }
      auto v = test::make_rank<dim>(rng, w, lo, hi, w.max_cutoff());
      n_owned += v.p.n_owned();
      VerletList<dim> list;
      list.build(v.p, w.cell, w.prm);
      EXPECT_FALSE(list.needs_rebuild(v.p, w.cell));
      ASSERT_EQ(list.n_owned(), v.p.n_owned());
      const auto mine = test::listed_pairs(list, v);
      EXPECT_EQ(mine.size(), list.n_pairs());
      // exactly the pairs of `expected` whose smaller-id grain this sub-box owns
      std::set<GlobalId> owned_ids(v.p.id.begin(), v.p.id.begin() + v.p.n_owned());
      std::set<PairKey<dim>> mine_expected;
      for (const auto& k : expected)
        if (owned_ids.count(std::get<0>(k)))
          mine_expected.insert(k);
      EXPECT_EQ(mine, mine_expected);
      n_listed += mine.size();
      all.insert(mine.begin(), mine.end());
      int a = dim - 1;
      while (a >= 0 && b[a] + 2 == cuts[a].size())
        b[a--] = 0;
      if (a < 0)
        break;
      ++b[a];
    }
    EXPECT_EQ(n_owned, w.s.size());
    EXPECT_EQ(n_listed, expected.size()) << "a pair computed on two sub-boxes";
    EXPECT_EQ(all, expected);
  }
}

// Everything owned by one rank; ghosts are the periodic images near the faces.
TYPED_TEST(VerletListTest, WholePeriodicSystemOnOneRankEqualsMinimumImage) {
  constexpr int dim = TypeParam::value;
  std::mt19937_64 rng(22);
  const auto w = TestFixture::world(rng);
  auto v = test::make_rank<dim>(rng, w, Vec<dim>::Zero(), Vec<dim>::Ones(), w.max_cutoff());
  ASSERT_EQ(v.p.n_owned(), w.s.size());
  ASSERT_GT(v.p.n_ghost(), 0u);
  VerletList<dim> list;
  list.build(v.p, w.cell, w.prm);
  const auto mine = test::listed_pairs(list, v);
  EXPECT_EQ(mine.size(), list.n_pairs());
  EXPECT_EQ(mine, test::brute_force_pairs(w, w.prm.range + w.prm.skin));
  // same pairs as (i, j) local indices, ascending j, via begin/end
  const auto local = test::local_brute_force(v.p, w.cell, w.prm.range + w.prm.skin);
  std::vector<std::pair<std::size_t, std::size_t>> got;
  for (std::size_t i = 0; i < list.n_owned(); ++i) {
    for (const auto* j = list.begin(i); j != list.end(i); ++j) {
      if (j != list.begin(i)) {
        EXPECT_LT(*(j - 1), *j);
      }
      got.emplace_back(i, *j);
    }
  }
  EXPECT_EQ(got, local);
}

// retain_pairs (a frozen contact network) keeps exactly the accepted pairs, in list order.
TYPED_TEST(VerletListTest, RetainPairsKeepsTheAcceptedPairsInOrder) {
  constexpr int dim = TypeParam::value;
  std::mt19937_64 rng(23);
  const auto w = TestFixture::world(rng);
  auto v = test::make_rank<dim>(rng, w, Vec<dim>::Zero(), Vec<dim>::Ones(), w.max_cutoff());
  VerletList<dim> list;
  list.build(v.p, w.cell, w.prm);
  const auto keep = [](std::size_t i, std::size_t j) { return (i + 2 * j) % 3 != 0; };
  std::vector<std::pair<std::size_t, std::size_t>> expected;
  list.for_each_pair([&](std::size_t i, std::size_t j) {
    if (keep(i, j))
      expected.emplace_back(i, j);
  });
  ASSERT_GT(expected.size(), 0u);
  ASSERT_LT(expected.size(), list.n_pairs());
  list.retain_pairs(keep);
  std::vector<std::pair<std::size_t, std::size_t>> got;
  list.for_each_pair([&](std::size_t i, std::size_t j) { got.emplace_back(i, j); });
  EXPECT_EQ(got, expected);
  EXPECT_EQ(list.n_pairs(), expected.size());
  EXPECT_EQ(list.offsets().back(), expected.size());
}

TYPED_TEST(VerletListTest, RejectsACellShorterThanTwoCutoffs) {
  constexpr int dim = TypeParam::value;
  ParticleStore<dim> p;
  Particle<dim> q;
  q.radius = 0.5;
  q.id = 1;
  p.add_owned(q);
  Cell<dim> cell;
  cell.length = Vec<dim>::Constant(10.0);
  cell.length[dim - 1] = 2 * (1.0 + 0.2 + 0.1) - 1e-9;
  VerletList<dim> list;
  EXPECT_TRUE(list.needs_rebuild(p, cell)); // never built
  EXPECT_THROW(list.build(p, cell, NeighborParams{0.2, 0.1}), Error);
  cell.length[dim - 1] = 2.7;
  EXPECT_NO_THROW(list.build(p, cell, NeighborParams{0.2, 0.1}));
  EXPECT_EQ(list.n_pairs(), 0u);
  EXPECT_DOUBLE_EQ(list.max_cutoff(), 1.3);
  EXPECT_THROW(list.build(p, cell, NeighborParams{-0.1, 0.0}), Error);
}

TYPED_TEST(VerletListTest, EmptyStoreAndNoGhosts) {
  constexpr int dim = TypeParam::value;
  ParticleStore<dim> p;
  Cell<dim> cell;
  cell.length = Vec<dim>::Constant(10.0);
  VerletList<dim> list;
  list.build(p, cell, NeighborParams{0.1, 0.0});
  EXPECT_EQ(list.n_owned(), 0u);
  EXPECT_EQ(list.n_pairs(), 0u);
  EXPECT_FALSE(list.needs_rebuild(p, cell));
  Particle<dim> q;
  q.radius = 0.5;
  q.id = 4;
  q.position = Vec<dim>::Constant(0.5);
  p.add_owned(q);
  EXPECT_TRUE(list.needs_rebuild(p, cell)); // particle count changed
  q.id = 2;
  q.position[0] += 0.105; // 1.05 apart: within 2R + skin
  p.add_owned(q);
  list.build(p, cell, NeighborParams{0.1, 0.0});
  ASSERT_EQ(list.n_pairs(), 1u);
  EXPECT_EQ(list.neighbors(1).size(), 1u); // the smaller id (index 1) holds the pair
  EXPECT_EQ(list.neighbors(1)[0], 0u);
  EXPECT_TRUE(list.neighbors(0).empty());
}

// Moves of at most skin/2 per grain: no rebuild asked, and no interacting pair missed.
TYPED_TEST(VerletListTest, MovesWithinHalfSkinMissNoContact) {
  constexpr int dim = TypeParam::value;
  std::mt19937_64 rng(23);
  auto w = TestFixture::world(rng);
  const Vec<dim> lo = Vec<dim>::Constant(0.2), hi = Vec<dim>::Constant(0.8);
  auto v = test::make_rank<dim>(rng, w, lo, hi, w.max_cutoff());
  VerletList<dim> list;
  list.build(v.p, w.cell, w.prm);
  // Every grain moves by 0.499 skin, towards its nearest grain (the worst case for contacts)
  // or in a random direction.
  std::normal_distribution<double> gauss;
  const auto s0 = w.s;
  for (std::size_t g = 0; g < w.s.size(); ++g) {
    Vec<dim> dir;
    if (g % 2 == 0) {
      double best = 1e300;
      for (std::size_t h = 0; h < w.s.size(); ++h) {
        if (h == g)
          continue;
        const Vec<dim> r = w.cell.min_image(s0[g], s0[h]);
        if (r.norm() < best) {
          best = r.norm();
          dir = r;
        }
      }
    } else {
      for (int a = 0; a < dim; ++a)
        dir[a] = gauss(rng);
    }
    w.s[g] += w.cell.to_scaled(0.499 * w.prm.skin * dir.normalized());
  }
  v.refresh(w);
  EXPECT_FALSE(list.needs_rebuild(v.p, w.cell));
  EXPECT_LE(list.drift(v.p, w.cell), w.prm.skin);
  const auto now = test::local_brute_force(v.p, w.cell, w.prm.range);
  ASSERT_FALSE(now.empty());
  for (const auto& [i, j] : now)
    EXPECT_TRUE(test::listed(list, i, j)) << i << " " << j;
}

TYPED_TEST(VerletListTest, MoveBeyondHalfSkinTriggersRebuild) {
  constexpr int dim = TypeParam::value;
  std::mt19937_64 rng(24);
  auto w = TestFixture::world(rng);
  auto v = test::make_rank<dim>(rng, w, Vec<dim>::Constant(0.1), Vec<dim>::Constant(0.6),
                                w.max_cutoff());
  VerletList<dim> list;
  list.build(v.p, w.cell, w.prm);
  Vec<dim> step = Vec<dim>::Zero();
  step[dim - 1] = 0.51 * w.prm.skin;
  for (std::size_t i : {std::size_t{0}, v.p.n_owned() + 3}) { // one owned grain, one ghost
    auto p = v.p;
    p.position[i] += w.cell.to_scaled(step);
    EXPECT_TRUE(list.needs_rebuild(p, w.cell)) << "particle " << i;
    EXPECT_NEAR(list.drift(p, w.cell), 1.02 * w.prm.skin, 1e-12);
    p.position[i] = v.p.position[i] + w.cell.to_scaled(0.49 * step / 0.51);
    EXPECT_FALSE(list.needs_rebuild(p, w.cell));
  }
  // a migration (fewer owned grains) always means a rebuild
  auto p = v.p;
  p.clear_ghosts();
  EXPECT_TRUE(list.needs_rebuild(p, w.cell));
}

TYPED_TEST(VerletListTest, CellShrinkTriggersRebuildGrowthDoesNot) {
  constexpr int dim = TypeParam::value;
  std::mt19937_64 rng(25);
  auto w = TestFixture::world(rng);
  auto v = test::make_rank<dim>(rng, w, Vec<dim>::Zero(), Vec<dim>::Constant(0.5), w.max_cutoff());
  VerletList<dim> list;
  list.build(v.p, w.cell, w.prm);
  const double eps_crit = w.prm.skin / list.max_cutoff();
  auto shrunk = [&](double eps) {
    Cell<dim> c = w.cell;
    c.length *= 1 - eps;
    return c;
  };
  EXPECT_TRUE(list.needs_rebuild(v.p, shrunk(1.01 * eps_crit)));
  EXPECT_FALSE(list.needs_rebuild(v.p, shrunk(1e-6)));
  EXPECT_FALSE(list.needs_rebuild(v.p, shrunk(-0.5))); // growth separates every pair
  {
    Cell<dim> c = w.cell; // one axis only
    c.length[0] *= 1 - 1.01 * eps_crit;
    EXPECT_TRUE(list.needs_rebuild(v.p, c));
  }
  // just below the threshold, every interacting pair of the shrunk cell is listed
  const Cell<dim> c = shrunk(0.99 * eps_crit);
  ASSERT_FALSE(list.needs_rebuild(v.p, c));
  const auto now = test::local_brute_force(v.p, c, w.prm.range);
  ASSERT_FALSE(now.empty());
  for (const auto& [i, j] : now)
    EXPECT_TRUE(test::listed(list, i, j));
}

// Many small random moves and anisotropic cell changes: whenever the list is not declared
// stale, it still holds every currently interacting pair. Two regimes: grain moves dominate,
// then a compression of the cell dominates (which the strain term of the criterion must catch).
TYPED_TEST(VerletListTest, RandomMovesAndCellChangesNeverMissAContact) {
  constexpr int dim = TypeParam::value;
  struct Regime {
    double move, strain_lo, strain_hi;
  };
  for (const Regime& regime : {Regime{0.02, -0.01, 0.01}, Regime{0.002, -0.004, 0.001}}) {
    std::mt19937_64 rng(26);
    auto w = TestFixture::world(rng, 0.2, 0.05);
    Vec<dim> lo = Vec<dim>::Constant(0.25), hi = Vec<dim>::Constant(0.75);
    lo[0] = 0.0;
    hi[0] = 1.0; // periodic along x on this rank
    auto v = test::make_rank<dim>(rng, w, lo, hi, w.max_cutoff() * 1.3);
    VerletList<dim> list;
    list.build(v.p, w.cell, w.prm);
    std::normal_distribution<double> gauss;
    std::uniform_real_distribution<double> u(regime.strain_lo, regime.strain_hi);
    int n_checked = 0, n_rebuilt = 0;
    std::size_t n_contacts = 0;
    for (int step = 0; step < 250; ++step) {
      for (auto& s : w.s) {
        Vec<dim> dr;
        for (int a = 0; a < dim; ++a)
          dr[a] = gauss(rng);
        s += w.cell.to_scaled(regime.move * w.prm.skin * dr);
      }
      for (int a = 0; a < dim; ++a)
        w.cell.length[a] *= 1 + u(rng);
      v.refresh(w);
      if (list.needs_rebuild(v.p, w.cell)) {
        list.build(v.p, w.cell, w.prm);
        ++n_rebuilt;
        continue;
      }
      ++n_checked;
      const auto now = test::local_brute_force(v.p, w.cell, w.prm.range);
      n_contacts += now.size();
      for (const auto& [i, j] : now)
        ASSERT_TRUE(test::listed(list, i, j)) << "step " << step << ": pair " << i << "-" << j;
    }
    EXPECT_GT(n_checked, 50);
    EXPECT_GE(n_rebuilt, 2);
    EXPECT_GT(n_contacts, 0u);
  }
}

} // namespace
} // namespace granpack
