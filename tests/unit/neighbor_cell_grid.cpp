// CellGrid: counting-sort binning, cell sizes, neighbour-cell stencil.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "granpack/core/error.h"
#include "granpack/neighbor/cell_grid.h"
#include "neighbor_fixtures.h"

namespace granpack {
namespace {

template <class D> class CellGridTest : public ::testing::Test {};
TYPED_TEST_SUITE(CellGridTest, test::Dims);

template <int dim>
std::vector<Vec<dim>> random_points(std::mt19937_64& rng, std::size_t n, double lo, double hi) {
  std::uniform_real_distribution<double> u(lo, hi);
  std::vector<Vec<dim>> r(n);
  for (auto& x : r)
    for (int a = 0; a < dim; ++a)
      x[a] = u(rng);
  return r;
}

TYPED_TEST(CellGridTest, BinsEveryParticleOnceInTheCellContainingIt) {
  constexpr int dim = TypeParam::value;
  std::mt19937_64 rng(11);
  const auto r = random_points<dim>(rng, 2000, -3.0, 7.0);
  CellGrid<dim> grid;
  const double side = 0.7;
  grid.build(r, side);
  ASSERT_EQ(grid.n_particles(), r.size());
  std::size_t nc = 1;
  for (int a = 0; a < dim; ++a) {
    EXPECT_GE(grid.side()[a], side);
    EXPECT_GE(grid.dims()[a], 10); // extent ~10 / 0.7
    nc *= static_cast<std::size_t>(grid.dims()[a]);
  }
  ASSERT_EQ(grid.n_cells(), nc);
  EXPECT_EQ(grid.cell_start(0), 0u);
  EXPECT_EQ(grid.cell_start(nc), r.size());
  std::vector<int> seen(r.size(), 0);
  for (std::size_t c = 0; c < nc; ++c) {
    ASSERT_LE(grid.cell_start(c), grid.cell_start(c + 1));
    for (std::size_t k = grid.cell_start(c); k < grid.cell_start(c + 1); ++k) {
      const std::size_t i = grid.order()[k];
      ++seen[i];
      EXPECT_EQ(grid.cell_of_particle(i), c);
      EXPECT_EQ(grid.sorted_position(k), r[i]);
      const auto ci = grid.coords_of(r[i]);
      for (int a = 0; a < dim; ++a) {
        EXPECT_GE(r[i][a], grid.lower()[a] + ci[a] * grid.side()[a] - 1e-12);
        if (ci[a] + 1 < grid.dims()[a]) {
          EXPECT_LE(r[i][a], grid.lower()[a] + (ci[a] + 1) * grid.side()[a] + 1e-12);
        }
      }
      if (k > grid.cell_start(c)) {
        EXPECT_LT(grid.order()[k - 1], grid.order()[k]); // stable within a cell
      }
    }
  }
  for (int s : seen)
    EXPECT_EQ(s, 1);
}

TYPED_TEST(CellGridTest, CloseParticlesAreInNeighbouringCells) {
  constexpr int dim = TypeParam::value;
  std::mt19937_64 rng(12);
  const auto r = random_points<dim>(rng, 800, 0.0, 5.0);
  CellGrid<dim> grid;
  const double side = 0.45;
  grid.build(r, side);
  for (std::size_t i = 0; i < r.size(); ++i) {
    std::vector<char> near(grid.n_cells(), 0);
    std::size_t n_stencil = 0;
    grid.for_each_neighbor_cell(grid.cell_of_particle(i), [&](std::size_t c) {
      ASSERT_LT(c, grid.n_cells());
      EXPECT_EQ(near[c], 0) << "stencil visits a cell twice";
      near[c] = 1;
      ++n_stencil;
    });
    EXPECT_LE(n_stencil, dim == 2 ? 9u : 27u);
    for (std::size_t j = 0; j < r.size(); ++j)
      if ((r[j] - r[i]).norm() < side) {
        EXPECT_TRUE(near[grid.cell_of_particle(j)]);
      }
  }
}

TYPED_TEST(CellGridTest, SparseSetDoesNotAllocateAHugeGrid) {
  constexpr int dim = TypeParam::value;
  std::mt19937_64 rng(13);
  const auto r = random_points<dim>(rng, 10, 0.0, 1e4);
  CellGrid<dim> grid;
  grid.build(r, 1e-3);
  EXPECT_LE(grid.n_cells(), 64u);
  for (int a = 0; a < dim; ++a)
    EXPECT_GE(grid.side()[a], 1e-3);
}

TYPED_TEST(CellGridTest, EmptyAndDegenerateInputs) {
  constexpr int dim = TypeParam::value;
  CellGrid<dim> grid;
  grid.build(std::vector<Vec<dim>>{}, 1.0);
  EXPECT_EQ(grid.n_particles(), 0u);
  EXPECT_EQ(grid.n_cells(), 1u);
  grid.build(std::vector<Vec<dim>>(5, Vec<dim>::Constant(2.0)), 1.0); // zero extent
  EXPECT_EQ(grid.n_cells(), 1u);
  EXPECT_EQ(grid.cell_start(1), 5u);
  EXPECT_THROW(grid.build(std::vector<Vec<dim>>(1, Vec<dim>::Zero()), 0.0), Error);
  Vec<dim> bad = Vec<dim>::Zero();
  bad[0] = std::nan("");
  EXPECT_THROW(grid.build(std::vector<Vec<dim>>{Vec<dim>::Zero(), bad}, 1.0), Error);
}

TYPED_TEST(CellGridTest, BuildsFromParticleStoreInRealUnits) {
  constexpr int dim = TypeParam::value;
  ParticleStore<dim> p;
  Cell<dim> cell;
  for (int a = 0; a < dim; ++a)
    cell.length[a] = 10.0 + a;
  Particle<dim> q;
  q.position = Vec<dim>::Constant(0.5);
  p.add_owned(q);
  q.position = Vec<dim>::Constant(-0.05); // a ghost image
  p.add_ghost(q);
  CellGrid<dim> grid;
  grid.build(p, cell, 1.0);
  EXPECT_EQ(grid.lower(), cell.to_real(Vec<dim>::Constant(-0.05)));
  for (int a = 0; a < dim; ++a)
    EXPECT_GE(grid.side()[a], 1.0);
  if constexpr (dim == 2) { // 5 x 6 cells over the 5.5 x 6.05 extent
    EXPECT_EQ(grid.dims()[0], 5);
    EXPECT_EQ(grid.dims()[1], 6);
  } else { // 5 x 6 x 6 would exceed the budget of 64 cells for 2 particles
    EXPECT_LE(grid.n_cells(), 64u);
  }
}

} // namespace
} // namespace granpack
