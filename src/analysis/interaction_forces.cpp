#include "granpack/analysis/interaction_forces.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

#include "granpack/core/error.h"

namespace granpack {

namespace {

/// Union-find whose elements carry their periodic image offset relative to their root.
template <int dim> class OffsetUnionFind {
public:
  using Offset = Eigen::Matrix<long, dim, 1>;
  explicit OffsetUnionFind(std::int64_t n) : parent_(n), offset_(n, Offset::Zero()), rank_(n, 0) {
    std::iota(parent_.begin(), parent_.end(), 0);
  }
  /// Root of x; `off` becomes x's image offset relative to the root.
  std::int64_t find(std::int64_t x, Offset& off) {
    off.setZero();
    std::int64_t r = x;
    while (parent_[r] != r) {
      off += offset_[r];
      r = parent_[r];
    }
    // Path compression: point every element of the path at the root with its total offset.
    Offset acc = off;
    while (parent_[x] != x) {
      const std::int64_t next = parent_[x];
      const Offset step = offset_[x];
      parent_[x] = r;
      offset_[x] = acc;
      acc -= step;
      x = next;
    }
    return r;
  }
  /// Joins i and j where j's image is at i's + shift. Returns the wrapping vector when i and
  /// j were already connected with another offset, zero otherwise; `root` is the common root.
  Offset join(std::int64_t i, std::int64_t j, const Offset& shift, std::int64_t& root) {
    Offset oi, oj;
    const std::int64_t ri = find(i, oi), rj = find(j, oj);
    if (ri == rj) {
      root = ri;
      return oi + shift - oj; // going round the cycle i -> j -> root -> i
    }
    // Attach the lower-rank root below the other: x_rj's image = x_ri + oi + shift - oj.
    if (rank_[ri] < rank_[rj]) {
      parent_[ri] = rj;
      offset_[ri] = oj - shift - oi;
      root = rj;
    } else {
      parent_[rj] = ri;
      offset_[rj] = oi + shift - oj;
      rank_[ri] += rank_[ri] == rank_[rj];
      root = ri;
    }
    return Offset::Zero();
  }

private:
  std::vector<std::int64_t> parent_;
  std::vector<Offset> offset_;
  std::vector<int> rank_;
};

template <int dim> int span_rank(const std::vector<Eigen::Matrix<long, dim, 1>>& v) {
  if (v.empty())
    return 0;
  Eigen::MatrixXd m(dim, v.size());
  for (std::size_t k = 0; k < v.size(); ++k)
    m.col(k) = v[k].template cast<double>();
  return static_cast<int>(Eigen::FullPivLU<Eigen::MatrixXd>(m).rank());
}

} // namespace

template <int dim>
PercolationResult percolation_threshold(std::vector<PercolationEdge<dim>> edges, std::int64_t n) {
  std::sort(edges.begin(), edges.end(), [](const auto& a, const auto& b) {
    if (a.force != b.force)
      return a.force > b.force;
    return a.i != b.i ? a.i < b.i : a.j < b.j;
  });
  OffsetUnionFind<dim> uf(n);
  // Wrapping vectors found so far, per root (merged when clusters merge).
  std::vector<std::vector<Eigen::Matrix<long, dim, 1>>> wraps(n);
  PercolationResult res;
  bool any = false;
  for (std::size_t k = 0; k < edges.size(); ++k) {
    const auto& e = edges[k];
    GRANPACK_CHECK(e.i >= 0 && e.i < n && e.j >= 0 && e.j < n,
                   "percolation_threshold: grain index out of range");
    typename OffsetUnionFind<dim>::Offset s;
    for (int a = 0; a < dim; ++a)
      s[a] = e.shift[a];
    typename OffsetUnionFind<dim>::Offset oi, oj;
    const std::int64_t ri = uf.find(e.i, oi), rj = uf.find(e.j, oj);
    std::int64_t root = 0;
    const auto w = uf.join(e.i, e.j, s, root);
    if (ri != rj) { // merge the wrap lists into the new root's
      const std::int64_t other = root == ri ? rj : ri;
      auto& into = wraps[root];
      into.insert(into.end(), wraps[other].begin(), wraps[other].end());
      wraps[other].clear();
      wraps[other].shrink_to_fit();
    } else if (!w.isZero()) {
      wraps[root].push_back(w);
    }
    if (wraps[root].empty())
      continue;
    if (!any) {
      any = true;
      res.threshold_any = e.force;
      res.edges_at_any = static_cast<std::int64_t>(k + 1);
    }
    if (span_rank<dim>(wraps[root]) == dim) {
      res.threshold_all = e.force;
      break;
    }
    // Keep the list short: only independent vectors matter.
    if (wraps[root].size() > dim) {
      std::vector<Eigen::Matrix<long, dim, 1>> basis;
      for (const auto& v : wraps[root]) {
        basis.push_back(v);
        if (span_rank<dim>(basis) < static_cast<int>(basis.size()))
          basis.pop_back();
      }
      wraps[root] = basis;
    }
  }
  return res;
}

void Histogram::add(double x) {
  if (x < lo) {
    below += 1;
  } else if (x >= hi) {
    above += 1;
  } else {
    const auto k = static_cast<std::size_t>((x - lo) / (hi - lo) * double(counts.size()));
    counts[std::min(k, counts.size() - 1)] += 1;
  }
}

double Histogram::total() const {
  return std::accumulate(counts.begin(), counts.end(), below + above);
}

std::vector<double> Histogram::pdf() const {
  const double t = total(), w = (hi - lo) / double(counts.size());
  std::vector<double> p(counts.size(), 0.0);
  if (t > 0)
    for (std::size_t k = 0; k < p.size(); ++k)
      p[k] = counts[k] / (t * w);
  return p;
}

std::vector<double> Histogram::edges() const {
  std::vector<double> e(counts.size() + 1);
  for (std::size_t k = 0; k < e.size(); ++k)
    e[k] = lo + (hi - lo) * double(k) / double(counts.size());
  return e;
}

double rumpf_mean_force(double pressure, double z, double phi, double mean_d,
                        double mean_d_pow_dim) {
  GRANPACK_CHECK(z > 0 && phi > 0 && mean_d > 0, "rumpf_mean_force: need z, Phi, <d> > 0");
  return std::numbers::pi * pressure * mean_d_pow_dim / (mean_d * z * phi);
}

template PercolationResult percolation_threshold<2>(std::vector<PercolationEdge<2>>, std::int64_t);
template PercolationResult percolation_threshold<3>(std::vector<PercolationEdge<3>>, std::int64_t);

} // namespace granpack
