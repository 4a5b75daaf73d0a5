#include "granpack/analysis/network_motifs.h"

#include <algorithm>

#include "granpack/core/error.h"

namespace granpack {

MotifSums::MotifSums(int max_triangles)
    : max_triangles_(max_triangles),
      sums_(static_cast<std::size_t>(kHistogramOffset + max_triangles + 1), 0.0) {
  GRANPACK_CHECK(max_triangles > 0, "MotifSums: max_triangles must be > 0");
}

void MotifSums::merge(const MotifSums& other) {
  GRANPACK_CHECK(other.max_triangles_ == max_triangles_, "MotifSums::merge: different layouts");
  for (std::size_t k = 0; k < sums_.size(); ++k)
    sums_[k] += other.sums_[k];
}

NetworkMotifs count_network_motifs(const MotifGraph& g, int max_triangles) {
  const std::size_t n = g.id.size();
  GRANPACK_CHECK(g.owned.size() == n, "count_network_motifs: id and owned differ in size");

  // Adjacency in compressed rows, sorted, without duplicates or self-loops.
  std::vector<std::size_t> degree(n + 1, 0);
  for (const auto& [i, j] : g.edges) {
    GRANPACK_CHECK(i < n && j < n,
                   "count_network_motifs: edge (" << i << ", " << j << ") outside the graph");
    if (i == j)
      continue;
    ++degree[i + 1];
    ++degree[j + 1];
  }
  std::vector<std::size_t> start(degree);
  for (std::size_t v = 0; v < n; ++v)
    start[v + 1] += start[v];
  std::vector<std::size_t> adj(start[n]);
  {
    std::vector<std::size_t> fill(start.begin(), start.end() - 1);
    for (const auto& [i, j] : g.edges) {
      if (i == j)
        continue;
      adj[fill[i]++] = j;
      adj[fill[j]++] = i;
    }
  }
  std::vector<std::size_t> end(n);
  for (std::size_t v = 0; v < n; ++v) {
    auto b = adj.begin() + static_cast<std::ptrdiff_t>(start[v]);
    auto e = adj.begin() + static_cast<std::ptrdiff_t>(start[v + 1]);
    std::sort(b, e);
    end[v] = static_cast<std::size_t>(std::unique(b, e) - adj.begin());
  }
  auto adjacent = [&](std::size_t u, std::size_t w) {
    return std::binary_search(adj.begin() + static_cast<std::ptrdiff_t>(start[u]),
                              adj.begin() + static_cast<std::ptrdiff_t>(end[u]), w);
  };

  NetworkMotifs out{std::vector<std::int64_t>(n, 0), std::vector<std::int64_t>(n, 0),
                    MotifSums(max_triangles)};
  auto& s = out.sums.sums();
  auto pairs = [](std::int64_t k) { return static_cast<double>(k * (k - 1) / 2); };
  std::vector<std::uint8_t> link; // adjacency among the neighbours of v
  for (std::size_t v = 0; v < n; ++v) {
    if (!g.owned[v])
      continue;
    const std::size_t* nb = adj.data() + start[v];
    const std::size_t deg = end[v] - start[v];
    if (deg == 0)
      continue;
    link.assign(deg * deg, 0);
    for (std::size_t a = 0; a < deg; ++a)
      for (std::size_t b = a + 1; b < deg; ++b)
        link[a * deg + b] = link[b * deg + a] = adjacent(nb[a], nb[b]) ? 1 : 0;
    auto linked = [&](std::size_t a, std::size_t b) { return link[a * deg + b] != 0; };
    auto above = [&](std::size_t a) { return g.id[v] < g.id[nb[a]]; }; // v is the anchor

    std::int64_t tri = 0, tet = 0, tri_anchored = 0, tet_anchored = 0;
    double edge_pairs = 0, face_pairs = 0;
    for (std::size_t a = 0; a < deg; ++a) {
      if (above(a)) { // edge {v, nb[a]} anchored at v: triangles on it
        std::int64_t k = 0;
        for (std::size_t b = 0; b < deg; ++b)
          k += linked(a, b) ? 1 : 0;
        edge_pairs += pairs(k);
      }
      for (std::size_t b = a + 1; b < deg; ++b) {
        if (!linked(a, b))
          continue;
        ++tri;
        const bool anchored = above(a) && above(b);
        if (anchored)
          ++tri_anchored;
        std::int64_t k = 0; // tetrahedra on the triangle (v, nb[a], nb[b])
        for (std::size_t c = 0; c < deg; ++c) {
          if (c == a || c == b || !linked(a, c) || !linked(b, c))
            continue;
          ++k;
          if (c > b) {
            ++tet;
            if (anchored && above(c))
              ++tet_anchored;
          }
        }
        if (anchored)
          face_pairs += pairs(k);
      }
    }
    out.triangles[v] = tri;
    out.tetrahedra[v] = tet;
    s[0] += 1;
    s[1] += static_cast<double>(tri);
    s[2] += static_cast<double>(tet);
    s[3] += tri > 0 ? 1 : 0;
    s[4] += tet > 0 ? 1 : 0;
    s[5] += static_cast<double>(tri_anchored);
    s[6] += static_cast<double>(tet_anchored);
    s[7] += edge_pairs;
    s[8] += face_pairs;
    s[static_cast<std::size_t>(MotifSums::kHistogramOffset) +
      static_cast<std::size_t>(std::min<std::int64_t>(tri, max_triangles))] += 1;
  }
  return out;
}

MotifStatistics finish_network_motifs(const MotifSums& sums) {
  const auto& s = sums.sums();
  MotifStatistics r;
  r.grains = s[0];
  r.triangles = s[5];
  r.tetrahedra = s[6];
  const double n = s[0] > 0 ? s[0] : 1.0; // no grain: every ratio is 0
  r.triangles_per_grain = s[1] / n;
  r.tetrahedra_per_grain = s[2] / n;
  r.fraction_in_triangle = s[3] / n;
  r.fraction_in_tetrahedron = s[4] / n;
  r.triangle_pairs_sharing_edge = s[7];
  r.tetrahedron_pairs_sharing_face = s[8];
  for (int t = 0; t <= sums.max_triangles(); ++t)
    r.triangle_histogram.push_back(s[static_cast<std::size_t>(MotifSums::kHistogramOffset + t)] /
                                   n);
  r.consistent = s[1] == 3 * s[5] && s[2] == 4 * s[6];
  return r;
}

} // namespace granpack
