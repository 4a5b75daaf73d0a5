#include "granpack/analysis/pivoting_clusters.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>

namespace granpack {

namespace {

/// (neighbour, edge) lists of the graph on dense indices.
using Adjacency = std::vector<std::vector<std::pair<int, int>>>;

/// Bridges by Tarjan's low-link, iteratively (chains of hanging grains can be long). Parallel
/// edges are told apart by their index, so a doubled pair is never a bridge.
std::vector<int> bridges(const Adjacency& adj) {
  const int n = int(adj.size());
  std::vector<int> order(n, -1), low(n, 0), out;
  int time = 0;
  struct Frame {
    int v, parent_edge;
    std::size_t next;
  };
  for (int root = 0; root < n; ++root) {
    if (order[root] >= 0)
      continue;
    std::vector<Frame> stack{{root, -1, 0}};
    order[root] = low[root] = time++;
    while (!stack.empty()) {
      Frame& f = stack.back();
      if (f.next < adj[f.v].size()) {
        const auto [w, e] = adj[f.v][f.next++];
        if (e == f.parent_edge)
          continue;
        if (order[w] < 0) {
          order[w] = low[w] = time++;
          stack.push_back({w, e, 0});
        } else {
          low[f.v] = std::min(low[f.v], order[w]);
        }
      } else {
        const Frame done = f;
        stack.pop_back();
        if (!stack.empty()) {
          const int u = stack.back().v;
          low[u] = std::min(low[u], low[done.v]);
          if (low[done.v] > order[u])
            out.push_back(done.parent_edge);
        }
      }
    }
  }
  return out;
}

} // namespace

std::vector<PivotingCluster> pivoting_clusters(const std::vector<NetworkEdge>& edges, double ell) {
  std::map<GlobalId, int> index;
  for (const auto& e : edges)
    index.emplace(e.i, 0), index.emplace(e.j, 0);
  std::vector<GlobalId> ids;
  for (auto& [id, k] : index)
    k = int(ids.size()), ids.push_back(id);
  Adjacency adj(ids.size());
  for (int e = 0; e < int(edges.size()); ++e) {
    const int a = index.at(edges[e].i), b = index.at(edges[e].j);
    adj[a].emplace_back(b, e);
    adj[b].emplace_back(a, e);
  }
  std::vector<PivotingCluster> out;
  for (const int hinge : bridges(adj)) {
    const NetworkEdge& h = edges[hinge];
    if (h.distant)
      continue; // a part held by one normal row keeps 5 free motions: not this mode
    // The two sides without the hinge: the part is the smaller.
    const int gi = index.at(h.i), gj = index.at(h.j);
    std::vector<int> side;
    std::vector<char> seen(ids.size(), 0);
    auto collect = [&](int start) {
      side.assign(1, start);
      std::fill(seen.begin(), seen.end(), 0);
      seen[start] = 1;
      for (std::size_t k = 0; k < side.size(); ++k)
        for (const auto& [w, e] : adj[side[k]])
          if (e != hinge && !seen[w])
            seen[w] = 1, side.push_back(w);
    };
    collect(gi);
    const std::size_t side_i = side.size();
    const bool part_is_i = 2 * side_i < ids.size() || (2 * side_i == ids.size() && h.i > h.j);
    if (!part_is_i)
      collect(gj);
    // Positions relative to the contact point p, from the hinge grain along the contacts
    // (x_j = x_i + r_ij): the part is a tree of bridges or holds cycles, either way each grain
    // is placed once.
    const Vec<3> r(h.r[0], h.r[1], h.r[2]), b_i(h.branch_i[0], h.branch_i[1], h.branch_i[2]);
    const int start = part_is_i ? gi : gj;
    std::vector<Vec<3>> pos(ids.size(), Vec<3>::Zero());
    std::fill(seen.begin(), seen.end(), 0);
    pos[start] = part_is_i ? Vec<3>(-b_i) : Vec<3>(r - b_i); // x - p; p = x_i + b_i
    seen[start] = 1;
    std::vector<int> queue{start};
    for (std::size_t k = 0; k < queue.size(); ++k)
      for (const auto& [w, e] : adj[queue[k]])
        if (e != hinge && !seen[w]) {
          const Vec<3> re(edges[e].r[0], edges[e].r[1], edges[e].r[2]);
          pos[w] = pos[queue[k]] + (index.at(edges[e].i) == queue[k] ? re : Vec<3>(-re));
          seen[w] = 1, queue.push_back(w);
        }
    PivotingCluster c;
    c.grain = part_is_i ? h.i : h.j;
    c.neighbour = part_is_i ? h.j : h.i;
    c.normal = (part_is_i ? r : Vec<3>(-r)).normalized();
    double norm2 = 0;
    for (const int k : queue) {
      Eigen::Matrix<double, 6, 1> v;
      v.head<3>() = c.normal.cross(pos[k]); // θ x (x - p), θ = n
      v.tail<3>() = ell * c.normal;
      norm2 += v.squaredNorm();
      c.mode.emplace_back(ids[k], v);
    }
    for (auto& [id, v] : c.mode)
      v /= std::sqrt(norm2);
    std::sort(c.mode.begin(), c.mode.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
    out.push_back(std::move(c));
  }
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) {
    return a.grain != b.grain ? a.grain < b.grain : a.neighbour < b.neighbour;
  });
  return out;
}

} // namespace granpack
