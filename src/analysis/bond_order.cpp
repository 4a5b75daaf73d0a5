#include "granpack/analysis/bond_order.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <numeric>

#include "granpack/core/cell.h"
#include "granpack/core/error.h"

namespace granpack {

namespace {

using Complex = std::complex<double>;

std::size_t n_coefficients(int l) {
  return static_cast<std::size_t>(2 * l + 1);
}

/// Y_lm(direction), m = -l..l, written to y[m + l] (y has 2l+1 entries).
void fill_spherical_harmonics(int l, const Vec<3>& d, Complex* y) {
  const double r = d.norm();
  GRANPACK_CHECK(std::isfinite(r) && r > 0.0,
                 "bond order: zero or non-finite bond vector (" << d.transpose() << ")");
  const double rho = std::hypot(d[0], d[1]);
  const double theta = std::atan2(rho, d[2]);                  // polar angle in [0, pi]
  const double phi = rho > 0.0 ? std::atan2(d[1], d[0]) : 0.0; // azimuth (any on the axis)
  const auto ul = static_cast<unsigned>(l);
  const auto il = static_cast<std::size_t>(l);
  for (unsigned m = 0; m <= ul; ++m) {
    // std::sph_legendre(l, m, theta) = Y_lm(theta, 0), Condon-Shortley phase included.
    const Complex ylm = std::sph_legendre(ul, m, theta) * std::polar(1.0, m * phi);
    y[il + m] = ylm;
    if (m > 0)
      y[il - m] = (m % 2 == 1 ? -1.0 : 1.0) * std::conj(ylm);
  }
}

} // namespace

QlmVector spherical_harmonics(int l, const Vec<3>& direction) {
  GRANPACK_CHECK(l >= 0, "spherical_harmonics: l = " << l << " < 0");
  QlmVector y(n_coefficients(l));
  fill_spherical_harmonics(l, direction, y.data());
  return y;
}

double rotational_invariant(std::span<const std::complex<double>> q) {
  GRANPACK_CHECK(q.size() % 2 == 1,
                 "rotational_invariant: " << q.size() << " coefficients, expected 2l+1");
  double s = 0.0;
  for (const auto& c : q)
    s += std::norm(c);
  return std::sqrt(4.0 * std::numbers::pi / static_cast<double>(q.size()) * s);
}

QlmVector LocalBondOrder::normalized() const {
  double s = 0.0;
  for (const auto& c : q)
    s += std::norm(c);
  QlmVector out(q.size(), Complex(0.0, 0.0));
  if (!(s > 0.0) || !std::isfinite(s))
    return out;
  const double inv = 1.0 / std::sqrt(s);
  for (std::size_t k = 0; k < q.size(); ++k)
    out[k] = q[k] * inv;
  return out;
}

LocalBondOrder local_q(std::span<const Vec<3>> bonds, int l) {
  GRANPACK_CHECK(l >= 0, "local_q: l = " << l << " < 0");
  LocalBondOrder r;
  r.l = l;
  r.n_bonds = static_cast<int>(bonds.size());
  r.q.assign(n_coefficients(l), Complex(0.0, 0.0));
  if (bonds.empty())
    return r;
  QlmVector y(n_coefficients(l));
  for (const auto& b : bonds) {
    fill_spherical_harmonics(l, b, y.data());
    for (std::size_t k = 0; k < y.size(); ++k)
      r.q[k] += y[k];
  }
  const double inv = 1.0 / static_cast<double>(bonds.size());
  for (auto& c : r.q)
    c *= inv;
  r.Q = rotational_invariant(r.q);
  return r;
}

LocalBondOrder local_q(const BondNeighborhood& grain, int l) {
  GRANPACK_CHECK(grain.bonds.size() == grain.neighbor_ids.size(),
                 "local_q: grain " << grain.id << " has " << grain.bonds.size() << " bonds but "
                                   << grain.neighbor_ids.size() << " neighbour ids");
  std::vector<std::size_t> order(grain.bonds.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return grain.neighbor_ids[a] < grain.neighbor_ids[b];
  });
  std::vector<Vec<3>> sorted;
  sorted.reserve(order.size());
  for (std::size_t k = 0; k < order.size(); ++k) {
    if (k > 0)
      GRANPACK_CHECK(grain.neighbor_ids[order[k]] != grain.neighbor_ids[order[k - 1]],
                     "local_q: grain " << grain.id << " is bonded twice to grain "
                                       << grain.neighbor_ids[order[k]]
                                       << " (d_c larger than half the cell?)");
    sorted.push_back(grain.bonds[order[k]]);
  }
  try {
    return local_q(std::span<const Vec<3>>(sorted), l);
  } catch (const Error& e) {
    throw Error("local_q, grain " + std::to_string(grain.id) + ": " + e.what());
  }
}

double bond_correlation(std::span<const std::complex<double>> qbar_a,
                        std::span<const std::complex<double>> qbar_b) {
  GRANPACK_CHECK(qbar_a.size() == qbar_b.size() && qbar_a.size() % 2 == 1,
                 "bond_correlation: sizes " << qbar_a.size() << " and " << qbar_b.size()
                                            << ", expected equal and 2l+1");
  // sum_m a_m b_m^*, real and imaginary parts written out (no library complex product).
  double re = 0.0, im = 0.0;
  for (std::size_t k = 0; k < qbar_a.size(); ++k) {
    re += qbar_a[k].real() * qbar_b[k].real() + qbar_a[k].imag() * qbar_b[k].imag();
    im += qbar_a[k].imag() * qbar_b[k].real() - qbar_a[k].real() * qbar_b[k].imag();
  }
  return std::hypot(re, im);
}

bool is_crystalline_bond(std::span<const std::complex<double>> qbar_i,
                         std::span<const std::complex<double>> qbar_j, double threshold) {
  return bond_correlation(qbar_i, qbar_j) >= threshold;
}

// ---------------------------------------------------------------------------------------------

QBarTable::QBarTable(int l) : l_(l) {
  GRANPACK_CHECK(l >= 0, "QBarTable: l = " << l << " < 0");
}

void QBarTable::insert(GlobalId id, std::span<const std::complex<double>> qbar) {
  const std::size_t n = n_coefficients(l_);
  GRANPACK_CHECK(qbar.size() == n, "QBarTable::insert: grain " << id << " has " << qbar.size()
                                                               << " coefficients, expected " << n);
  auto [it, fresh] = index_.try_emplace(id, ids_.size());
  if (fresh) {
    ids_.push_back(id);
    values_.insert(values_.end(), qbar.begin(), qbar.end());
  } else {
    const auto offset = static_cast<std::ptrdiff_t>(it->second * n);
    std::copy(qbar.begin(), qbar.end(), values_.begin() + offset);
  }
}

std::span<const std::complex<double>> QBarTable::find(GlobalId id) const {
  auto it = index_.find(id);
  if (it == index_.end())
    return {};
  const std::size_t n = n_coefficients(l_);
  return std::span<const std::complex<double>>(values_.data() + it->second * n, n);
}

std::vector<GlobalId> crystalline_neighbors(const BondNeighborhood& grain, const QBarTable& qbar,
                                            double threshold) {
  const auto qi = qbar.find(grain.id);
  GRANPACK_CHECK(!qi.empty(), "crystalline_neighbors: no qbar for grain " << grain.id);
  std::vector<GlobalId> out;
  for (const GlobalId j : grain.neighbor_ids) {
    const auto qj = qbar.find(j);
    GRANPACK_CHECK(!qj.empty(), "crystalline_neighbors: no qbar for grain "
                                    << j << ", neighbour of " << grain.id
                                    << " (the halo must cover d_c)");
    // Smaller id first: both ends of the bond evaluate the very same expression.
    const double c = grain.id < j ? bond_correlation(qi, qj) : bond_correlation(qj, qi);
    if (c >= threshold)
      out.push_back(j);
  }
  return out;
}

// ---------------------------------------------------------------------------------------------

GlobalQlSum::GlobalQlSum(int l_) : l(l_), sum_y(n_coefficients(l_ < 0 ? 0 : l_)) {
  GRANPACK_CHECK(l_ >= 0 && l_ % 2 == 0,
                 "GlobalQlSum: l = " << l_
                                     << "; only even l >= 0 (bonds are met in both "
                                        "directions, odd l would vanish identically)");
}

void GlobalQlSum::add(const LocalBondOrder& grain) {
  GRANPACK_CHECK(grain.l == l && grain.q.size() == sum_y.size(),
                 "GlobalQlSum::add: l = " << grain.l << ", expected " << l);
  const double nb = static_cast<double>(grain.n_bonds);
  for (std::size_t k = 0; k < sum_y.size(); ++k)
    sum_y[k] += grain.q[k] * nb;
  n_bonds += grain.n_bonds;
}

void GlobalQlSum::merge(const GlobalQlSum& other) {
  GRANPACK_CHECK(other.l == l, "GlobalQlSum::merge: l = " << other.l << ", expected " << l);
  for (std::size_t k = 0; k < sum_y.size(); ++k)
    sum_y[k] += other.sum_y[k];
  n_bonds += other.n_bonds;
}

double GlobalQlSum::value() const {
  if (n_bonds == 0)
    return 0.0;
  QlmVector mean(sum_y);
  const double inv = 1.0 / static_cast<double>(n_bonds);
  for (auto& c : mean)
    c *= inv;
  return rotational_invariant(mean);
}

void BondOrderTally::add(const LocalBondOrder& q6, int crystalline_bonds,
                         int min_crystalline_bonds) {
  GRANPACK_CHECK(q6.l == 6, "BondOrderTally::add: l = " << q6.l << ", expected 6");
  ++n_grains;
  n_bonds += q6.n_bonds;
  n_crystalline_bonds += crystalline_bonds;
  if (q6.n_bonds > 0) {
    ++n_grains_with_bonds;
    sum_q6_loc += q6.Q;
  }
  if (crystalline_bonds >= min_crystalline_bonds) {
    ++n_crystalline_grains;
    sum_q6_loc_crystalline += q6.Q;
  }
  global_q6.add(q6);
}

void BondOrderTally::merge(const BondOrderTally& o) {
  n_grains += o.n_grains;
  n_grains_with_bonds += o.n_grains_with_bonds;
  n_bonds += o.n_bonds;
  n_crystalline_bonds += o.n_crystalline_bonds;
  n_crystalline_grains += o.n_crystalline_grains;
  sum_q6_loc += o.sum_q6_loc;
  sum_q6_loc_crystalline += o.sum_q6_loc_crystalline;
  global_q6.merge(o.global_q6);
}

namespace {
double ratio(double num, std::int64_t den) {
  return den == 0 ? 0.0 : num / static_cast<double>(den);
}
} // namespace

double BondOrderTally::z() const {
  return ratio(static_cast<double>(n_bonds), n_grains);
}
double BondOrderTally::z_cr() const {
  return ratio(static_cast<double>(n_crystalline_bonds), n_grains);
}
double BondOrderTally::q6_loc() const {
  return ratio(sum_q6_loc, n_grains_with_bonds);
}
double BondOrderTally::q6_loc_cr() const {
  return ratio(sum_q6_loc_crystalline, n_crystalline_grains);
}
double BondOrderTally::x_cr() const {
  return ratio(static_cast<double>(n_crystalline_grains), n_grains);
}

std::vector<double> BondOrderTally::packed() const {
  std::vector<double> v = {static_cast<double>(n_grains),
                           static_cast<double>(n_grains_with_bonds),
                           static_cast<double>(n_bonds),
                           static_cast<double>(n_crystalline_bonds),
                           static_cast<double>(n_crystalline_grains),
                           sum_q6_loc,
                           sum_q6_loc_crystalline,
                           static_cast<double>(global_q6.n_bonds)};
  for (const auto& c : global_q6.sum_y) {
    v.push_back(c.real());
    v.push_back(c.imag());
  }
  return v;
}

BondOrderTally BondOrderTally::unpacked(std::span<const double> v) {
  BondOrderTally t;
  const std::size_t n_y = t.global_q6.sum_y.size();
  GRANPACK_CHECK(v.size() == kPackedHeader + 2 * n_y,
                 "BondOrderTally::unpacked: " << v.size() << " values, expected "
                                              << kPackedHeader + 2 * n_y);
  auto count = [&](std::size_t k) { return static_cast<std::int64_t>(std::llround(v[k])); };
  t.n_grains = count(0);
  t.n_grains_with_bonds = count(1);
  t.n_bonds = count(2);
  t.n_crystalline_bonds = count(3);
  t.n_crystalline_grains = count(4);
  t.sum_q6_loc = v[5];
  t.sum_q6_loc_crystalline = v[6];
  t.global_q6.n_bonds = count(7);
  for (std::size_t k = 0; k < n_y; ++k)
    t.global_q6.sum_y[k] = Complex(v[kPackedHeader + 2 * k], v[kPackedHeader + 2 * k + 1]);
  return t;
}

// ---------------------------------------------------------------------------------------------

CrystallineClusters crystalline_clusters(
    const std::vector<GlobalId>& crystalline_grains,
    const std::vector<std::pair<GlobalId, GlobalId>>& crystalline_bonds_between_them) {
  const std::size_t n = crystalline_grains.size();
  std::unordered_map<GlobalId, std::size_t> index;
  index.reserve(n);
  for (std::size_t k = 0; k < n; ++k) {
    const bool fresh = index.try_emplace(crystalline_grains[k], k).second;
    GRANPACK_CHECK(fresh,
                   "crystalline_clusters: grain " << crystalline_grains[k] << " listed twice");
  }
  // Union-find with path halving and union by size.
  std::vector<std::size_t> parent(n), size(n, 1);
  std::iota(parent.begin(), parent.end(), std::size_t{0});
  auto find = [&](std::size_t x) {
    while (parent[x] != x) {
      parent[x] = parent[parent[x]];
      x = parent[x];
    }
    return x;
  };
  for (const auto& [a, b] : crystalline_bonds_between_them) {
    const auto ia = index.find(a), ib = index.find(b);
    if (ia == index.end() || ib == index.end())
      continue; // other end not crystalline
    std::size_t ra = find(ia->second), rb = find(ib->second);
    if (ra == rb)
      continue;
    if (size[ra] < size[rb])
      std::swap(ra, rb);
    parent[rb] = ra;
    size[ra] += size[rb];
  }
  // Components, each with its size and smallest member id, ordered for a deterministic labelling
  // (independent of the input order and of the rank count that produced it).
  struct Component {
    std::int64_t size = 0;
    GlobalId min_id = 0;
  };
  std::unordered_map<std::size_t, std::size_t> component_of_root;
  std::vector<Component> comps;
  std::vector<std::size_t> comp_of(n);
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t r = find(k);
    auto [it, fresh] = component_of_root.try_emplace(r, comps.size());
    if (fresh)
      comps.push_back({0, crystalline_grains[k]});
    Component& c = comps[it->second];
    ++c.size;
    c.min_id = std::min(c.min_id, crystalline_grains[k]);
    comp_of[k] = it->second;
  }
  std::vector<std::size_t> rank(comps.size());
  std::iota(rank.begin(), rank.end(), std::size_t{0});
  std::sort(rank.begin(), rank.end(), [&](std::size_t a, std::size_t b) {
    if (comps[a].size != comps[b].size)
      return comps[a].size > comps[b].size;
    return comps[a].min_id < comps[b].min_id;
  });
  std::vector<std::size_t> label(comps.size());
  CrystallineClusters out;
  out.sizes.reserve(comps.size());
  for (std::size_t k = 0; k < rank.size(); ++k) {
    label[rank[k]] = k;
    out.sizes.push_back(comps[rank[k]].size);
  }
  out.cluster_of.resize(n);
  for (std::size_t k = 0; k < n; ++k)
    out.cluster_of[k] = label[comp_of[k]];
  std::int64_t s1 = 0, s2 = 0;
  for (const auto s : out.sizes) {
    s1 += s;
    s2 += s * s;
  }
  out.mass_average_size = s1 == 0 ? 0.0 : static_cast<double>(s2) / static_cast<double>(s1);
  return out;
}

// ---------------------------------------------------------------------------------------------

std::string_view to_string(LocalOrder kind) {
  switch (kind) {
  case LocalOrder::disordered:
    return "dis";
  case LocalOrder::fcc:
    return "fcc";
  case LocalOrder::hcp:
    return "hcp";
  }
  return "?";
}

bool OrderWindow::contains(double Q4, double Q6) const {
  return std::abs(Q4 - q4) <= half_width && std::abs(Q6 - q6) <= half_width;
}

namespace {
using LO = LocalOrder;
using AS = AsteSample;
// [AR] appendix D: fcc-like (0.191 +- 0.05, 0.574 +- 0.05), hcp-like (0.097 +- 0.05,
// 0.485 +- 0.05); "dis" = the most frequent (Q^4, Q^6) measured by Aste et al. per sample and
// d_c (tables VII and VIII, column (Q^4, Q^6)), with the same +- 0.05 half-widths.
constexpr OrderWindow kWindows[] = {
    {LO::fcc, 0.191, 0.574, 0.05, AS::any, 0.0, "[AR] app. D text and tables VII-VIII (fcc)"},
    {LO::hcp, 0.097, 0.485, 0.05, AS::any, 0.0, "[AR] app. D text and tables VII-VIII (hcp)"},
    {LO::disordered, 0.23, 0.44, 0.05, AS::F, 1.1, "[AR] table VII, Aste F (Phi 0.640), d_c 1.1a"},
    {LO::disordered, 0.16, 0.45, 0.05, AS::F, 1.2, "[AR] table VII, Aste F (Phi 0.640), d_c 1.2a"},
    {LO::disordered, 0.13, 0.42, 0.05, AS::F, 1.3, "[AR] table VII, Aste F (Phi 0.640), d_c 1.3a"},
    {LO::disordered, 0.10, 0.38, 0.05, AS::F, 1.4, "[AR] table VII, Aste F (Phi 0.640), d_c 1.4a"},
    {LO::disordered, 0.25, 0.44, 0.05, AS::D, 1.1, "[AR] table VIII, Aste D (Phi 0.626), d_c 1.1a"},
    {LO::disordered, 0.19, 0.44, 0.05, AS::D, 1.2, "[AR] table VIII, Aste D (Phi 0.626), d_c 1.2a"},
    {LO::disordered, 0.15, 0.40, 0.05, AS::D, 1.3, "[AR] table VIII, Aste D (Phi 0.626), d_c 1.3a"},
    {LO::disordered, 0.11, 0.36, 0.05, AS::D, 1.4, "[AR] table VIII, Aste D (Phi 0.626), d_c 1.4a"},
    {LO::disordered, 0.30, 0.45, 0.05, AS::B, 1.1, "[AR] table VIII, Aste B (Phi 0.596), d_c 1.1a"},
    {LO::disordered, 0.23, 0.44, 0.05, AS::B, 1.2, "[AR] table VIII, Aste B (Phi 0.596), d_c 1.2a"},
    {LO::disordered, 0.16, 0.38, 0.05, AS::B, 1.3, "[AR] table VIII, Aste B (Phi 0.596), d_c 1.3a"},
    {LO::disordered, 0.14, 0.35, 0.05, AS::B, 1.4, "[AR] table VIII, Aste B (Phi 0.596), d_c 1.4a"},
};
} // namespace

std::span<const OrderWindow> order_windows() {
  return kWindows;
}

std::vector<OrderWindow> windows_for(AsteSample sample, double d_c_over_a) {
  std::vector<OrderWindow> out;
  for (const auto& w : kWindows)
    if (w.kind == LocalOrder::disordered && w.sample == sample &&
        std::abs(w.d_c_over_a - d_c_over_a) <= 1e-9)
      out.push_back(w);
  if (out.empty())
    throw InputError("bond order windows: no [AR] table VII/VIII \"dis\" window for d_c = " +
                     std::to_string(d_c_over_a) +
                     " a (tabulated: 1.1, 1.2, 1.3, 1.4 a, samples F, D, B)");
  for (const auto& w : kWindows)
    if (w.kind != LocalOrder::disordered)
      out.push_back(w);
  return out;
}

AsteSample aste_sample_compared_with(std::string_view ar_state) {
  if (ar_state == "A" || ar_state == "A'" || ar_state == "C")
    return AsteSample::F;
  if (ar_state == "B")
    return AsteSample::D;
  if (ar_state == "D")
    return AsteSample::B;
  throw InputError("bond order windows: [AR] compares only states A, A', B, C, D with "
                   "Aste et al. (got '" +
                   std::string(ar_state) + "')");
}

std::vector<std::size_t> windows_containing(double Q4, double Q6,
                                            std::span<const OrderWindow> windows) {
  std::vector<std::size_t> out;
  for (std::size_t k = 0; k < windows.size(); ++k)
    if (windows[k].contains(Q4, Q6))
      out.push_back(k);
  return out;
}

// ---------------------------------------------------------------------------------------------

std::vector<BondNeighborhood> periodic_neighborhoods(const std::vector<Vec<3>>& real_positions,
                                                     const Vec<3>& lengths, double d_c) {
  GRANPACK_CHECK(lengths.minCoeff() > 0.0 && std::isfinite(lengths.maxCoeff()),
                 "periodic_neighborhoods: bad cell lengths " << lengths.transpose());
  GRANPACK_CHECK(d_c > 0.0 && d_c < 0.5 * lengths.minCoeff(),
                 "periodic_neighborhoods: d_c = " << d_c << " must be in (0, min L / 2 = "
                                                  << 0.5 * lengths.minCoeff() << ")");
  Cell<3> cell;
  cell.length = lengths;
  const std::size_t n = real_positions.size();
  std::vector<Vec<3>> s(n);
  for (std::size_t i = 0; i < n; ++i) {
    GRANPACK_CHECK(real_positions[i].allFinite(),
                   "periodic_neighborhoods: non-finite position of grain " << i);
    s[i] = Cell<3>::wrap(cell.to_scaled(real_positions[i]));
  }
  // Periodic bins of side >= d_c in scaled space (at least one per axis).
  std::array<int, 3> nb{};
  for (int a = 0; a < 3; ++a)
    nb[static_cast<std::size_t>(a)] = std::max(1, static_cast<int>(std::floor(lengths[a] / d_c)));
  auto bin_coord = [&](const Vec<3>& si, int a) {
    const int k = static_cast<int>(si[a] * nb[static_cast<std::size_t>(a)]);
    return std::min(k, nb[static_cast<std::size_t>(a)] - 1);
  };
  auto flat = [&](int x, int y, int z) {
    return (static_cast<std::size_t>(x) * static_cast<std::size_t>(nb[1]) +
            static_cast<std::size_t>(y)) *
               static_cast<std::size_t>(nb[2]) +
           static_cast<std::size_t>(z);
  };
  const std::size_t n_bins = static_cast<std::size_t>(nb[0]) * static_cast<std::size_t>(nb[1]) *
                             static_cast<std::size_t>(nb[2]);
  std::vector<std::vector<std::size_t>> bins(n_bins);
  for (std::size_t i = 0; i < n; ++i)
    bins[flat(bin_coord(s[i], 0), bin_coord(s[i], 1), bin_coord(s[i], 2))].push_back(i);

  const double dc2 = d_c * d_c;
  std::vector<BondNeighborhood> out(n);
  std::vector<std::size_t> near_bins;
  std::vector<std::size_t> cand;
  for (std::size_t i = 0; i < n; ++i) {
    const int cx = bin_coord(s[i], 0), cy = bin_coord(s[i], 1), cz = bin_coord(s[i], 2);
    near_bins.clear();
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz)
          near_bins.push_back(flat((cx + dx + nb[0]) % nb[0], (cy + dy + nb[1]) % nb[1],
                                   (cz + dz + nb[2]) % nb[2]));
    std::sort(near_bins.begin(), near_bins.end()); // fewer than 3 bins on an axis: duplicates
    near_bins.erase(std::unique(near_bins.begin(), near_bins.end()), near_bins.end());
    cand.clear();
    for (const auto b : near_bins)
      cand.insert(cand.end(), bins[b].begin(), bins[b].end());
    std::sort(cand.begin(), cand.end());
    BondNeighborhood& g = out[i];
    g.id = static_cast<GlobalId>(i);
    for (const auto j : cand) {
      if (j == i)
        continue;
      const Vec<3> r = cell.min_image(s[i], s[j]);
      if (r.squaredNorm() < dc2) {
        g.bonds.push_back(r);
        g.neighbor_ids.push_back(static_cast<GlobalId>(j));
      }
    }
  }
  return out;
}

BondOrderResult bond_order_periodic(const std::vector<Vec<3>>& real_positions,
                                    const Vec<3>& lengths, const BondOrderParams& params) {
  const auto hoods = periodic_neighborhoods(real_positions, lengths, params.d_c);
  const std::size_t n = hoods.size();
  BondOrderResult res;
  res.grains.resize(n);
  // Stage 1: local order; the qbar_6m table (a driver exchanges its ghost part here).
  std::vector<LocalBondOrder> q6(n);
  QBarTable table(6);
  for (std::size_t i = 0; i < n; ++i) {
    q6[i] = local_q(hoods[i], 6);
    auto& g = res.grains[i];
    g.id = hoods[i].id;
    g.n_bonds = q6[i].n_bonds;
    g.q6 = q6[i].Q;
    g.q4 = local_q(hoods[i], 4).Q;
    table.insert(g.id, q6[i].normalized());
  }
  // Stages 2-3: crystalline bonds, tally; stage 4 input: crystalline grains and their bonds.
  std::vector<GlobalId> cryst;
  std::vector<std::pair<GlobalId, GlobalId>> cryst_bonds;
  for (std::size_t i = 0; i < n; ++i) {
    const auto cn = crystalline_neighbors(hoods[i], table, params.threshold);
    auto& g = res.grains[i];
    g.n_crystalline_bonds = static_cast<int>(cn.size());
    g.crystalline = g.n_crystalline_bonds >= params.min_crystalline_bonds;
    res.tally.add(q6[i], g.n_crystalline_bonds, params.min_crystalline_bonds);
    if (!g.crystalline)
      continue;
    cryst.push_back(g.id);
    for (const GlobalId j : cn)
      if (g.id < j)
        cryst_bonds.emplace_back(g.id, j);
  }
  res.clusters = crystalline_clusters(cryst, cryst_bonds);
  return res;
}

} // namespace granpack
