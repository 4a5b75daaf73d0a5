// Per-grain order of /network (analysis/local_order.h) and the cluster names of
// analysis/disjoint_sets.h on closed forms: fcc grains have Q6 = (169/512)^1/2 = 0.57452 with
// 12 bonds, a triangular lattice |psi6| = 1 with 6 bonds, a square lattice |psi6| = 0, an
// ideal gas low values; two separate clusters get two names, their smallest ids.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "granpack/analysis/bond_order.h"
#include "granpack/analysis/disjoint_sets.h"
#include "granpack/analysis/local_order.h"
#include "lattice_fixtures.h"

namespace granpack {
namespace {

/// Owned grains at the scaled positions, and their periodic images within one cell length as
/// ghosts (what the halo gives the engine: neighbours across the boundary).
template <int dim> ParticleStore<dim> with_images(const std::vector<Vec<dim>>& scaled) {
  ParticleStore<dim> p;
  auto add = [&](bool owned, std::size_t i, const Vec<dim>& shift) {
    Particle<dim> g;
    g.id = GlobalId(i);
    g.radius = 0.5;
    g.position = scaled[i] + shift;
    owned ? p.add_owned(g) : p.add_ghost(g);
  };
  for (std::size_t i = 0; i < scaled.size(); ++i)
    add(true, i, Vec<dim>::Zero());
  const int images = dim == 2 ? 9 : 27;
  for (int k = 0; k < images; ++k) {
    Vec<dim> shift;
    int rest = k;
    for (int a = 0; a < dim; ++a, rest /= 3)
      shift[a] = double(rest % 3 - 1);
    if (shift.norm() == 0)
      continue;
    for (std::size_t i = 0; i < scaled.size(); ++i)
      add(false, i, shift);
  }
  return p;
}

TEST(LocalOrder3D, FccGrainsHaveQ6OfThePerfectLattice) {
  // Conventional cubic cells of side sqrt(2): nearest neighbours at 1 (12 of them), the next
  // shell at sqrt(2) > d_c = 1.4.
  const int m = 3;
  Cell<3> cell;
  cell.length = Vec<3>::Constant(m * std::sqrt(2.0));
  std::vector<Vec<3>> s;
  const Vec<3> basis[4] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
  for (int x = 0; x < m; ++x)
    for (int y = 0; y < m; ++y)
      for (int z = 0; z < m; ++z)
        for (const auto& b : basis)
          s.push_back((Vec<3>(x, y, z) + b) / m);
  const auto bonds = grain_bonds(cell, with_images(s), kOrderCutoff);
  ASSERT_EQ(bonds.size(), s.size());
  for (const auto& g : bonds) {
    ASSERT_EQ(g.bonds.size(), 12u);
    const LocalBondOrder q = local_q(BondNeighborhood{g.id, g.bonds, g.neighbor_ids}, 6);
    EXPECT_NEAR(q.Q, std::sqrt(169.0 / 512.0), 1e-12);
  }
}

TEST(LocalOrder2D, TriangularLatticeHasUnitPsi6AndSquareLatticeNone) {
  Cell<2> cell;
  const auto s = test::triangular_lattice(4, 3, cell);
  for (const auto& g : grain_bonds(cell, with_images(s), kOrderCutoff)) {
    ASSERT_EQ(g.bonds.size(), 6u);
    EXPECT_NEAR(psi6_modulus(g.bonds), 1.0, 1e-12);
    EXPECT_GE(psi6_modulus(g.bonds), kCrystallinePsi6);
  }
  // Square lattice of unit spacing: bonds at 0, 90, 180, 270 degrees, exp(6 i theta) = +-1.
  Cell<2> sq;
  sq.length = Vec<2>(5, 5);
  std::vector<Vec<2>> q;
  for (int x = 0; x < 5; ++x)
    for (int y = 0; y < 5; ++y)
      q.push_back(Vec<2>(x, y) / 5.0);
  for (const auto& g : grain_bonds(sq, with_images(q), kOrderCutoff)) {
    ASSERT_EQ(g.bonds.size(), 4u);
    EXPECT_NEAR(psi6_modulus(g.bonds), 0.0, 1e-12);
  }
}

// Ideal gases (uniform random centres, about 13 bonds per grain in 3D, 6 in 2D): for N_b
// isotropic bonds E[Q_l^2] = E|psi6|^2 = 1/N_b, far below the lattices' values.
TEST(LocalOrder, RandomGasHasLowOrder) {
  std::mt19937_64 rng(6);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  {
    Cell<3> cell;
    cell.length = Vec<3>::Constant(6.0);
    std::vector<Vec<3>> s(250); // density 250/216: 13 within 1.4 on average
    for (auto& x : s)
      x = Vec<3>(u(rng), u(rng), u(rng));
    double sum = 0, n = 0;
    for (const auto& g : grain_bonds(cell, with_images(s), kOrderCutoff))
      if (!g.bonds.empty()) {
        sum += local_q(BondNeighborhood{g.id, g.bonds, g.neighbor_ids}, 6).Q, n += 1;
      }
    EXPECT_LT(sum / n, 0.35); // about 0.28
    EXPECT_GT(sum / n, 0.2);
  }
  {
    Cell<2> cell;
    cell.length = Vec<2>(12.0, 12.0);
    std::vector<Vec<2>> s(140); // 6 within 1.4 on average
    for (auto& x : s)
      x = Vec<2>(u(rng), u(rng));
    double sum = 0, flagged = 0;
    const auto bonds = grain_bonds(cell, with_images(s), kOrderCutoff);
    for (const auto& g : bonds) {
      sum += psi6_modulus(g.bonds);
      flagged += psi6_modulus(g.bonds) >= kCrystallinePsi6;
    }
    EXPECT_LT(sum / double(bonds.size()), 0.5);
    EXPECT_LT(flagged / double(bonds.size()), 0.15);
  }
}

TEST(ClusterNames, TwoSeparateClustersGetTheirSmallestIds) {
  // 7-3-9 and 4-12, 12-5: two clusters, whatever the order of the links.
  std::vector<std::pair<GlobalId, GlobalId>> links = {{7, 3}, {12, 5}, {9, 3}, {4, 12}};
  for (int turn = 0; turn < 2; ++turn) {
    const auto name = smallest_member(links);
    ASSERT_EQ(name.size(), 6u);
    for (GlobalId id : {3, 7, 9})
      EXPECT_EQ(name.at(id), 3);
    for (GlobalId id : {4, 5, 12})
      EXPECT_EQ(name.at(id), 4);
    std::reverse(links.begin(), links.end());
  }
  // One link between them makes one cluster.
  links.emplace_back(9, 5);
  for (const auto& [id, name] : smallest_member(links))
    EXPECT_EQ(name, 3) << id;
}

} // namespace
} // namespace granpack
