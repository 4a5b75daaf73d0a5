#pragma once
// Triangles and tetrahedra (3- and 4-cliques) of the force-carrying contact network ([AR]
// sec. III D: each backbone grain of state A belongs to 2.04 triangles on average; tetrahedra
// involve about 2.5% of the grains; pairs of tetrahedra sharing a face are exceptional; pairs
// of triangles sharing an edge explain the drop of g(r) at r = a sqrt(3)).
// docs/analysis-statistics.md.
//
// Distributed use (MPI-free here). The graph is one rank's: vertices = local particles
// (owned + ghosts) with their global ids, edges = backbone contacts by local index. For the
// counts at an owned vertex v to be complete, the graph must hold every edge between two
// neighbours of v, ghost-ghost edges included: every backbone contact between two local
// particles each of which is an owned vertex or adjacent to one. Duplicated edges and
// self-loops are ignored. Each clique is also counted once over all ranks, at its vertex of
// smallest global id when that vertex is owned ("anchored" counts); sum_v T(v) = 3 T and
// sum_v Q(v) = 4 Q must then hold after the reduction (MotifStatistics::consistent).
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "granpack/core/vec.h"

namespace granpack {

/// One rank's piece of the contact network.
struct MotifGraph {
  std::vector<GlobalId> id;                               ///< global id of each local vertex
  std::vector<std::uint8_t> owned;                        ///< 1: owned by this rank
  std::vector<std::pair<std::size_t, std::size_t>> edges; ///< local indices, any order
};

/// Partial sums over one rank's owned vertices; flat layout of sums():
///   [0] owned vertices with at least one edge (the backbone grains counted)
///   [1] sum over them of T(v), triangles containing v
///   [2] sum of Q(v), tetrahedra (4-cliques) containing v
///   [3] vertices with T(v) > 0, [4] vertices with Q(v) > 0
///   [5] anchored triangles, [6] anchored tetrahedra
///   [7] pairs of triangles sharing an edge (sum over edges of C(k, 2), k triangles on the
///       edge; each edge anchored at its smaller-id end)
///   [8] pairs of tetrahedra sharing a triangle (sum over triangles of C(k, 2), anchored)
///   [9 + t] vertices with T(v) = t for t < max_triangles, [9 + max_triangles] T(v) >= max.
class MotifSums {
public:
  explicit MotifSums(int max_triangles = 48);

  void merge(const MotifSums& other);
  std::vector<double>& sums() { return sums_; }
  const std::vector<double>& sums() const { return sums_; }
  int max_triangles() const { return max_triangles_; }

  static constexpr int kHistogramOffset = 9;

private:
  int max_triangles_;
  std::vector<double> sums_;
};

/// Per local vertex counts (0 for vertices that are not owned) and the rank's partial sums.
struct NetworkMotifs {
  std::vector<std::int64_t> triangles;  ///< T(v)
  std::vector<std::int64_t> tetrahedra; ///< Q(v)
  MotifSums sums;
};

/// Counts the cliques at every owned vertex of the graph (degree <= ~15 in a packing: the
/// cost is O(sum_v deg(v)^3)).
NetworkMotifs count_network_motifs(const MotifGraph& graph, int max_triangles = 48);

/// Final numbers from the globally summed partials.
struct MotifStatistics {
  double grains = 0;                    ///< backbone grains (vertices with an edge)
  double triangles = 0, tetrahedra = 0; ///< T, Q (anchored counts)
  double triangles_per_grain = 0;       ///< sum_v T(v) / grains ([AR]: 2.04 in state A)
  double tetrahedra_per_grain = 0;      ///< sum_v Q(v) / grains
  double fraction_in_triangle = 0;      ///< grains with T(v) > 0 / grains
  double fraction_in_tetrahedron = 0;   ///< grains with Q(v) > 0 / grains ([AR]: ~2.5%)
  double triangle_pairs_sharing_edge = 0;
  double tetrahedron_pairs_sharing_face = 0;
  std::vector<double> triangle_histogram; ///< fraction of grains with T(v) = t (last: >= max)
  bool consistent = true; ///< sum_v T(v) == 3 T and sum_v Q(v) == 4 Q (complete halos)
};

MotifStatistics finish_network_motifs(const MotifSums& sums);

} // namespace granpack
