#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <vector>

#include "granpack/analysis/network_motifs.h"
#include "granpack/core/cell.h"
#include "lattice_fixtures.h"

using namespace granpack;

namespace {

using Edge = std::pair<std::size_t, std::size_t>;

/// The whole graph on one rank: every vertex owned, global id ids[v].
MotifGraph whole(std::size_t n, const std::vector<Edge>& edges, std::vector<GlobalId> ids = {}) {
  MotifGraph g;
  if (ids.empty())
    for (std::size_t v = 0; v < n; ++v)
      ids.push_back(static_cast<GlobalId>(v));
  g.id = ids;
  g.owned.assign(n, 1);
  g.edges = edges;
  return g;
}

/// The piece of `edges` rank r sees when it owns the vertices with owner[v] == r: owned
/// vertices first, then ghosts = their neighbours, and every edge between two local vertices
/// (ghost-ghost included), renumbered locally.
MotifGraph rank_piece(std::size_t n, const std::vector<Edge>& edges,
                      const std::vector<GlobalId>& ids, const std::vector<int>& owner, int r) {
  std::vector<std::size_t> local(n, n);
  MotifGraph g;
  auto take = [&](std::size_t v, bool own) {
    if (local[v] != n)
      return;
    local[v] = g.id.size();
    g.id.push_back(ids[v]);
    g.owned.push_back(own ? 1 : 0);
  };
  for (std::size_t v = 0; v < n; ++v)
    if (owner[v] == r)
      take(v, true);
  for (const auto& [i, j] : edges) {
    if (owner[i] == r)
      take(j, false);
    if (owner[j] == r)
      take(i, false);
  }
  for (const auto& [i, j] : edges)
    if (local[i] != n && local[j] != n)
      g.edges.emplace_back(local[i], local[j]);
  return g;
}

/// Brute-force reference: triangles and 4-cliques per vertex, pairs of triangles on an edge,
/// pairs of tetrahedra on a triangle.
struct Reference {
  std::vector<std::int64_t> tri, tet;
  double triangles = 0, tetrahedra = 0, edge_pairs = 0, face_pairs = 0;
};
Reference brute_force(std::size_t n, const std::vector<Edge>& edges) {
  std::vector<std::vector<char>> adj(n, std::vector<char>(n, 0));
  for (const auto& [i, j] : edges)
    if (i != j)
      adj[i][j] = adj[j][i] = 1;
  Reference ref{std::vector<std::int64_t>(n, 0), std::vector<std::int64_t>(n, 0)};
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j) {
      if (!adj[i][j])
        continue;
      double on_edge = 0;
      for (std::size_t k = 0; k < n; ++k)
        on_edge += adj[i][k] && adj[j][k];
      ref.edge_pairs += on_edge * (on_edge - 1) / 2;
      for (std::size_t k = j + 1; k < n; ++k) {
        if (!adj[i][k] || !adj[j][k])
          continue;
        ++ref.triangles, ++ref.tri[i], ++ref.tri[j], ++ref.tri[k];
        double on_face = 0;
        for (std::size_t l = 0; l < n; ++l)
          on_face += adj[i][l] && adj[j][l] && adj[k][l];
        ref.face_pairs += on_face * (on_face - 1) / 2;
        for (std::size_t l = k + 1; l < n; ++l)
          if (adj[i][l] && adj[j][l] && adj[k][l])
            ++ref.tetrahedra, ++ref.tet[i], ++ref.tet[j], ++ref.tet[k], ++ref.tet[l];
      }
    }
  return ref;
}

/// The contact network of an FCC crystal at contact: 4 x 4 x 4 cubic cells, 256 grains.
std::vector<Edge> fcc_edges(std::vector<Vec<3>>& s) {
  const int cells = 4;
  Cell<3> cell;
  cell.length = Vec<3>::Constant(cells * std::sqrt(2.0));
  const double basis[4][3] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
  s.clear();
  for (int x = 0; x < cells; ++x)
    for (int y = 0; y < cells; ++y)
      for (int z = 0; z < cells; ++z)
        for (const auto& b : basis)
          s.push_back(Vec<3>(x + b[0], y + b[1], z + b[2]) / cells);
  std::vector<Edge> e;
  for (std::size_t i = 0; i < s.size(); ++i)
    for (std::size_t j = i + 1; j < s.size(); ++j)
      if (cell.min_image(s[i], s[j]).norm() < 1 + 1e-9)
        e.emplace_back(i, j);
  return e;
}

/// Sums the partials of the given pieces ("ranks").
MotifSums reduce(const std::vector<MotifGraph>& pieces) {
  MotifSums total;
  for (const auto& g : pieces)
    total.merge(count_network_motifs(g).sums);
  return total;
}

} // namespace

TEST(NetworkMotifs, SingleTetrahedron) {
  // Duplicated edges (either orientation) and a self-loop are ignored.
  const std::vector<Edge> e = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3},
                               {2, 3}, {3, 2}, {1, 0}, {2, 2}};
  const auto m = count_network_motifs(whole(4, e));
  for (std::size_t v = 0; v < 4; ++v) {
    EXPECT_EQ(m.triangles[v], 3);
    EXPECT_EQ(m.tetrahedra[v], 1);
  }
  const auto st = finish_network_motifs(m.sums);
  EXPECT_EQ(st.grains, 4);
  EXPECT_EQ(st.triangles, 4);
  EXPECT_EQ(st.tetrahedra, 1);
  EXPECT_EQ(st.triangle_pairs_sharing_edge, 6); // each edge on 2 triangles
  EXPECT_EQ(st.tetrahedron_pairs_sharing_face, 0);
  EXPECT_TRUE(st.consistent);
  EXPECT_EQ(st.fraction_in_tetrahedron, 1);
  EXPECT_EQ(st.triangle_histogram[3], 1);
}

TEST(NetworkMotifs, Octahedron) {
  // Six vertices, opposite pairs (0,1), (2,3), (4,5) not joined: 12 edges, 8 faces.
  std::vector<Edge> e;
  for (std::size_t i = 0; i < 6; ++i)
    for (std::size_t j = i + 1; j < 6; ++j)
      if (j != i + 1 || i % 2 == 1)
        e.emplace_back(i, j);
  ASSERT_EQ(e.size(), 12u);
  const auto m = count_network_motifs(whole(6, e, {60, 10, 30, 50, 20, 40}));
  for (std::size_t v = 0; v < 6; ++v) {
    EXPECT_EQ(m.triangles[v], 4);
    EXPECT_EQ(m.tetrahedra[v], 0);
  }
  const auto st = finish_network_motifs(m.sums);
  EXPECT_EQ(st.triangles, 8);
  EXPECT_EQ(st.tetrahedra, 0);
  EXPECT_EQ(st.triangles_per_grain, 4);
  EXPECT_EQ(st.triangle_pairs_sharing_edge, 12);
  EXPECT_TRUE(st.consistent);
}

TEST(NetworkMotifs, FccEachGrainIn24TrianglesAnd8Tetrahedra) {
  // FCC: two nearest neighbours share 4 nearest neighbours -> 12 * 4 / 2 = 24 triangles per
  // grain; 2 tetrahedral holes per grain, 4 grains each -> 8 tetrahedra per grain. Each
  // triangle is a face of exactly one tetrahedron (and one octahedron): no face pairs.
  std::vector<Vec<3>> s;
  const auto e = fcc_edges(s);
  const std::size_t n = s.size();
  ASSERT_EQ(e.size(), 6 * n);
  const auto m = count_network_motifs(whole(n, e));
  for (std::size_t v = 0; v < n; ++v) {
    EXPECT_EQ(m.triangles[v], 24);
    EXPECT_EQ(m.tetrahedra[v], 8);
  }
  const auto st = finish_network_motifs(m.sums);
  EXPECT_EQ(st.triangles, 8.0 * double(n));
  EXPECT_EQ(st.tetrahedra, 2.0 * double(n));
  EXPECT_EQ(st.triangle_pairs_sharing_edge, 36.0 * double(n)); // 6 edges/grain, C(4,2) each
  EXPECT_EQ(st.tetrahedron_pairs_sharing_face, 0);
  EXPECT_EQ(st.triangle_histogram[24], 1);
  EXPECT_TRUE(st.consistent);

  // Two "ranks" split by x < 1/2: the same totals, and the same per-grain counts.
  std::vector<int> owner(n);
  std::vector<GlobalId> ids(n);
  for (std::size_t v = 0; v < n; ++v) {
    owner[v] = s[v][0] < 0.5 ? 0 : 1;
    ids[v] = static_cast<GlobalId>(v);
  }
  const auto split = reduce({rank_piece(n, e, ids, owner, 0), rank_piece(n, e, ids, owner, 1)});
  EXPECT_EQ(split.sums(), m.sums.sums());
}

TEST(NetworkMotifs, RandomGraphMatchesBruteForceOnOneAndTwoRanks) {
  std::mt19937_64 rng(99);
  std::bernoulli_distribution coin(0.3);
  const std::size_t n = 40;
  std::vector<Edge> e;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j)
      if (coin(rng))
        e.emplace_back(i, j);
  std::vector<GlobalId> ids(n);
  for (std::size_t v = 0; v < n; ++v)
    ids[v] = static_cast<GlobalId>(1000 + 7 * v);
  std::shuffle(ids.begin(), ids.end(), rng); // anchors are not the local order

  const auto ref = brute_force(n, e);
  ASSERT_GT(ref.tetrahedra, 10); // the test must exercise 4-cliques
  const auto m = count_network_motifs(whole(n, e, ids));
  EXPECT_EQ(m.triangles, ref.tri);
  EXPECT_EQ(m.tetrahedra, ref.tet);
  const auto st = finish_network_motifs(m.sums);
  EXPECT_EQ(st.triangles, ref.triangles);
  EXPECT_EQ(st.tetrahedra, ref.tetrahedra);
  EXPECT_EQ(st.triangle_pairs_sharing_edge, ref.edge_pairs);
  EXPECT_EQ(st.tetrahedron_pairs_sharing_face, ref.face_pairs);
  EXPECT_TRUE(st.consistent);

  // Three ownership patterns over two ranks.
  for (int pattern = 0; pattern < 3; ++pattern) {
    std::vector<int> owner(n);
    for (std::size_t v = 0; v < n; ++v)
      owner[v] = pattern == 0 ? int(v % 2) : pattern == 1 ? int(v < 13) : int(ids[v] % 3 == 0);
    const auto split = reduce({rank_piece(n, e, ids, owner, 0), rank_piece(n, e, ids, owner, 1)});
    EXPECT_EQ(split.sums(), m.sums.sums()) << "pattern " << pattern;
    // Leaving out the ghost-ghost edges loses cliques.
    auto p0 = rank_piece(n, e, ids, owner, 0), p1 = rank_piece(n, e, ids, owner, 1);
    for (auto* p : {&p0, &p1})
      std::erase_if(p->edges,
                    [&](const Edge& x) { return !p->owned[x.first] && !p->owned[x.second]; });
    const auto lossy = finish_network_motifs(reduce({p0, p1}));
    EXPECT_LT(lossy.triangles, ref.triangles) << "pattern " << pattern;
  }
}

TEST(NetworkMotifs, TriangularLatticeHasSixTrianglesPerGrainAndNoTetrahedron) {
  const int nx = 6, ny = 4;
  Cell<2> cell;
  const std::vector<Vec<2>> s = test::triangular_lattice(nx, ny, cell);
  std::vector<Edge> e;
  for (std::size_t i = 0; i < s.size(); ++i)
    for (std::size_t j = i + 1; j < s.size(); ++j)
      if (cell.min_image(s[i], s[j]).norm() < 1 + 1e-9)
        e.emplace_back(i, j);
  const auto st = finish_network_motifs(count_network_motifs(whole(s.size(), e)).sums);
  EXPECT_EQ(st.triangles_per_grain, 6);
  EXPECT_EQ(st.tetrahedra, 0);
  EXPECT_EQ(st.triangles, 2.0 * double(s.size()));
}
