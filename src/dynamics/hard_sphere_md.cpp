#include "granpack/dynamics/hard_sphere_md.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <utility>

#include "granpack/core/error.h"

namespace granpack {

namespace {

/// Doubles the row capacity of a table of fixed-capacity rows (row r: rows[r * cap + m],
/// m < count[r]; the cells' members and the neighbour lists), keeping each row's entries.
void double_row_capacity(std::vector<std::int32_t>& rows, int& cap,
                         const std::vector<std::int32_t>& count) {
  const int wider = 2 * cap;
  std::vector<std::int32_t> mem(count.size() * static_cast<std::size_t>(wider), -1);
  for (std::size_t r = 0; r < count.size(); ++r)
    std::copy_n(&rows[r * cap], count[r], &mem[r * wider]);
  rows.swap(mem);
  cap = wider;
}

/// Cells are at least (1 + margin) times the diameter they were built for, so a grain that
/// sits a rounding error outside its nominal cell is still found by its neighbours.
constexpr double kCellMargin = 1e-9;
/// Overlap accepted at construction, relative to the sum of radii.
constexpr double kOverlapTol = 1e-9;
/// During growth a grid is built for diameters up to (1 + kGrowthHeadroom) times the current.
constexpr double kGrowthHeadroom = 0.01;
/// LS growth has jammed when, over kStallWindows windows of n collisions each, the grains
/// travel less than kStallPath mean diameters (v_rms times the elapsed time): the mean free
/// path is then at the level of round-off and the time no longer advances.
constexpr double kStallPath = 1e-12;
constexpr int kStallWindows = 3;
/// Neighbour lists: a grain may move kShell largest diameters from its list centre before its
/// list is rebuilt; the lists reach centre distances of sum of radii + 2 kShell d_max. Measured
/// on the melt of deck A (n = 4000, phi = 0.45; docs/performance.md): 0.1 -> 6.9e5, 0.15 ->
/// 7.5e5, 0.2 -> 8.0e5, 0.25 -> 8.4e5, 0.3 -> 8.5e5, 0.4 -> 7.1e5 collisions per CPU s:
/// thinner shells rebuild too often, thicker ones predict too many pairs.
constexpr double kShell = 0.25;

template <int dim> double ball_volume(double r) {
  if constexpr (dim == 3)
    return 4.0 / 3.0 * std::numbers::pi * r * r * r;
  else
    return std::numbers::pi * r * r;
}

/// x wrapped into [0, l).
double wrap(double x, double l) {
  x -= l * std::floor(x / l);
  return (x >= l || x < 0.0) ? 0.0 : x;
}

/// Time to the first root of a t^2 + 2 b t + c = 0 for t >= 0 where the gap closes, or +inf.
/// a = |v|^2 - sigma'^2, b = r.v - sigma sigma', c = |r|^2 - sigma^2 (r, v: relative position
/// and velocity; sigma(t) = sigma + sigma' t the contact distance). The caller has already
/// rejected b >= 0 && a >= 0 (never closer). `dr_norm_rate` is r.v - |r| sigma' (the rate of
/// the gap |r| - sigma, times |r|), used only when the pair touches or overlaps (c <= 0).
inline double first_contact(double a, double b, double c, double dr_norm_rate) {
  if (c <= 0.0)
    return dr_norm_rate < 0.0 ? 0.0 : std::numeric_limits<double>::infinity();
  const double disc = b * b - a * c;
  if (b < 0.0) {
    if (disc < 0.0)
      return std::numeric_limits<double>::infinity(); // a > 0: misses
    return c / (-b + std::sqrt(disc));                // no cancellation
  }
  // b >= 0 and a < 0: growth overtakes the separation; disc > b^2 > 0.
  return (b + std::sqrt(disc)) / (-a);
}

} // namespace

// ---------------------------------------------------------------------------------------
// Construction and accessors

template <int dim>
HardSphereMD<dim>::HardSphereMD(const Vec<dim>& box, std::vector<Vec<dim>> positions,
                                std::vector<double> radii, std::vector<double> masses,
                                std::vector<Vec<dim>> velocities)
    : box_(box), half_box_(0.5 * box), mass_(std::move(masses)) {
  const std::size_t n = positions.size();
  GRANPACK_CHECK(n > 0, "HardSphereMD: no particles");
  GRANPACK_CHECK(radii.size() == n && mass_.size() == n && velocities.size() == n,
                 "HardSphereMD: " << n << " positions but " << radii.size() << " radii, "
                                  << mass_.size() << " masses, " << velocities.size()
                                  << " velocities");
  GRANPACK_CHECK(n < static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()),
                 "HardSphereMD: too many particles (" << n << ")");
  for (int a = 0; a < dim; ++a)
    GRANPACK_CHECK(std::isfinite(box[a]) && box[a] > 0,
                   "HardSphereMD: box length " << a << " is " << box[a]);
  st_.resize(n);
  inv_mass_.resize(n);
  double rmax = 0;
  for (std::size_t i = 0; i < n; ++i) {
    GRANPACK_CHECK(std::isfinite(radii[i]) && radii[i] > 0,
                   "HardSphereMD: radius of particle " << i << " is " << radii[i]);
    GRANPACK_CHECK(std::isfinite(mass_[i]) && mass_[i] > 0,
                   "HardSphereMD: mass of particle " << i << " is " << mass_[i]);
    GRANPACK_CHECK(positions[i].allFinite() && velocities[i].allFinite(),
                   "HardSphereMD: non-finite position or velocity of particle " << i);
    State& s = st_[i];
    for (int a = 0; a < dim; ++a)
      s.x[a] = wrap(positions[i][a], box_[a]);
    s.t = 0;
    s.v = velocities[i];
    s.rb = radii[i];
    inv_mass_[i] = 1.0 / mass_[i];
    rmax = std::max(rmax, radii[i]);
  }
  for (int a = 0; a < dim; ++a)
    GRANPACK_CHECK(0.5 * box_[a] > 2 * rmax * (1 + 2 * kCellMargin),
                   "HardSphereMD: box length " << box_[a] << " along axis " << a
                                               << " must exceed two largest diameters (" << 4 * rmax
                                               << ")");
  count_.assign(n, 0);
  slots_.assign(n, Slot{});
  out_pos_.resize(n);
  out_vel_.resize(n);
  out_radii_.resize(n);
  build_cells(2 * rmax);

  int pi = -1, pj = -1;
  const double gap = min_gap_pair(&pi, &pj);
  GRANPACK_CHECK(gap >= -kOverlapTol, "HardSphereMD: particles " << pi << " and " << pj
                                                                 << " overlap by " << -gap
                                                                 << " of the sum of their radii");
  k_track_ = kinetic_energy();
  sync_output();
}

template <int dim> double HardSphereMD<dim>::kinetic_energy() const {
  double k = 0;
  for (std::size_t i = 0; i < st_.size(); ++i)
    k += 0.5 * mass_[i] * st_[i].v.squaredNorm();
  return k;
}

template <int dim> Vec<dim> HardSphereMD<dim>::momentum() const {
  Vec<dim> p = Vec<dim>::Zero();
  for (std::size_t i = 0; i < st_.size(); ++i)
    p += mass_[i] * st_[i].v;
  return p;
}

template <int dim> double HardSphereMD<dim>::solid_fraction() const {
  double v = 0;
  for (const State& s : st_)
    v += ball_volume<dim>(s.rb * g_now_);
  return v / box_.prod();
}

template <int dim> double HardSphereMD<dim>::pressure() const {
  const double vol = box_.prod();
  const double t_acc = t_now_ - t_press0_;
  if (!(t_acc > 0))
    return 2 * kinetic_energy() / (dim * vol);
  const double kin = kin_integral_ + k_track_ * (t_now_ - t_kin_);
  return (2 * kin + virial_) / (dim * vol * t_acc);
}

template <int dim> void HardSphereMD<dim>::reset_pressure() {
  t_press0_ = t_now_;
  virial_ = 0;
  kin_integral_ = 0;
  t_kin_ = t_now_;
  k_track_ = kinetic_energy();
}

template <int dim> double HardSphereMD<dim>::min_relative_gap() const {
  return min_gap_pair(nullptr, nullptr);
}

template <int dim> double HardSphereMD<dim>::min_gap_pair(int* pi, int* pj) const {
  double worst = kInf;
  const int n = static_cast<int>(st_.size());
  for (int i = 0; i < n; ++i) {
    const State& si = st_[i];
    const Vec<dim> xi = si.x + (t_now_ - si.t) * si.v;
    for_stencil(cc_[i], -1, 0, [&](int c) {
      const std::int32_t* mem = &members_[static_cast<std::size_t>(c) * cap_];
      for (int m = 0; m < count_in_[c]; ++m) {
        const int k = mem[m];
        if (k <= i)
          continue;
        const State& sk = st_[k];
        Vec<dim> dr = sk.x + (t_now_ - sk.t) * sk.v - xi;
        min_image(dr);
        const double sig = (si.rb + sk.rb) * g_now_;
        const double gap = (dr.norm() - sig) / sig;
        if (gap < worst) {
          worst = gap;
          if (pi)
            *pi = i;
          if (pj)
            *pj = k;
        }
      }
    });
  }
  return worst;
}

template <int dim> void HardSphereMD<dim>::sync_output() {
  for (std::size_t i = 0; i < st_.size(); ++i) {
    const State& s = st_[i];
    const Vec<dim> x = s.x + (t_now_ - s.t) * s.v;
    for (int a = 0; a < dim; ++a)
      out_pos_[i][a] = wrap(x[a], box_[a]);
    out_vel_[i] = s.v;
    out_radii_[i] = s.rb * g_now_;
  }
}

// ---------------------------------------------------------------------------------------
// Cell list

template <int dim> void HardSphereMD<dim>::min_image(Vec<dim>& d) const {
  for (int a = 0; a < dim; ++a) {
    if (d[a] > half_box_[a])
      d[a] -= box_[a];
    else if (d[a] < -half_box_[a])
      d[a] += box_[a];
  }
}

template <int dim> int HardSphereMD<dim>::flat(const std::array<int, dim>& c) const {
  int f = 0;
  for (int a = 0; a < dim; ++a)
    if (real_[a])
      f += stride_[a] * c[a];
  return f;
}

template <int dim> void HardSphereMD<dim>::build_cells(double d_allow) {
  const std::size_t n = st_.size();
  nl_ = false;
  const double d_cell = d_allow * (1 + kCellMargin);
  // Side of a real cell: at least the diameter allowance, and at most ~4 cells per grain, so
  // a dilute gas does not allocate a huge empty grid.
  const double side =
      std::max(d_cell, std::pow(box_.prod() / (4.0 * static_cast<double>(n)), 1.0 / dim));
  bool all_real = true;
  long total = 1;
  for (int a = 0; a < dim; ++a) {
    const double m = std::floor(box_[a] / side);
    if (m >= 4) {
      real_[a] = true;
      ncross_[a] = static_cast<int>(std::min(m, 1e6));
      cw_[a] = box_[a] / ncross_[a];
      stride_[a] = static_cast<int>(total);
      total *= ncross_[a];
    } else {
      // All pairs along this axis. A pair's minimum image can only change when the relative
      // displacement passes half the box; re-predicting every time a grain has moved
      // (L/2 - d)/2 keeps the image of every stored prediction right (docs/event-driven.md).
      real_[a] = false;
      all_real = false;
      const double room = 0.5 * box_[a] - d_cell;
      GRANPACK_CHECK(room > 0, "HardSphereMD: box length " << box_[a] << " along axis " << a
                                                           << " is not larger than two diameters ("
                                                           << 2 * d_allow << ")");
      const double slabs = std::ceil(box_[a] / (0.5 * room));
      GRANPACK_CHECK(slabs < 1e8, "HardSphereMD: box length " << box_[a] << " along axis " << a
                                                              << " is too close to two diameters ("
                                                              << 2 * d_allow
                                                              << ") for the all-pairs fallback");
      ncross_[a] = static_cast<int>(slabs);
      cw_[a] = box_[a] / ncross_[a];
      stride_[a] = 0;
    }
  }
  GRANPACK_CHECK(total < (1L << 30), "HardSphereMD: too many cells (" << total << ")");
  d_lim_ = d_allow;
  if (all_real) {
    d_lim_ = kInf;
    for (int a = 0; a < dim; ++a)
      d_lim_ = std::min(d_lim_, cw_[a] / (1 + kCellMargin));
  }
  cap_ = 8;
  count_in_.assign(static_cast<std::size_t>(total), 0);
  members_.assign(static_cast<std::size_t>(total) * cap_, -1);
  cell_of_.assign(n, -1);
  slot_in_cell_.assign(n, -1);
  cc_.resize(n);
  cand_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    State& s = st_[i];
    for (int a = 0; a < dim; ++a) {
      s.x[a] = wrap(s.x[a], box_[a]);
      const int c = static_cast<int>(std::floor(s.x[a] / cw_[a]));
      cc_[i][a] = std::clamp(c, 0, ncross_[a] - 1);
    }
    cell_insert(static_cast<int>(i), flat(cc_[i]));
  }
}

template <int dim> void HardSphereMD<dim>::cell_insert(int i, int c) {
  if (count_in_[c] == cap_)
    grow_cell_capacity();
  const int m = count_in_[c]++;
  members_[static_cast<std::size_t>(c) * cap_ + m] = i;
  cell_of_[i] = c;
  slot_in_cell_[i] = m;
}

template <int dim> void HardSphereMD<dim>::cell_remove(int i) {
  const int c = cell_of_[i];
  std::int32_t* mem = &members_[static_cast<std::size_t>(c) * cap_];
  const int last = --count_in_[c];
  const int moved = mem[last];
  mem[slot_in_cell_[i]] = moved;
  slot_in_cell_[moved] = slot_in_cell_[i];
}

/// Doubles the capacity of every cell (rare: only when a cell overflows).
template <int dim> void HardSphereMD<dim>::grow_cell_capacity() {
  double_row_capacity(members_, cap_, count_in_);
}

/// Calls f(cell) for the cells of the 3^dim block around slab coordinates c (one cell along
/// the all-pairs axes); along `fixed_axis` (if >= 0) only the layer at `fixed_coord`.
template <int dim>
template <class F>
void HardSphereMD<dim>::for_stencil(const std::array<int, dim>& c, int fixed_axis, int fixed_coord,
                                    F&& f) const {
  std::array<std::array<int, 3>, dim> off;
  std::array<int, dim> cnt;
  for (int a = 0; a < dim; ++a) {
    if (!real_[a]) {
      off[a][0] = 0;
      cnt[a] = 1;
    } else if (a == fixed_axis) {
      off[a][0] = fixed_coord * stride_[a];
      cnt[a] = 1;
    } else {
      const int n = ncross_[a];
      off[a][0] = (c[a] == 0 ? n - 1 : c[a] - 1) * stride_[a];
      off[a][1] = c[a] * stride_[a];
      off[a][2] = (c[a] + 1 == n ? 0 : c[a] + 1) * stride_[a];
      cnt[a] = 3;
    }
  }
  if constexpr (dim == 2) {
    for (int j = 0; j < cnt[1]; ++j)
      for (int i = 0; i < cnt[0]; ++i)
        f(off[0][i] + off[1][j]);
  } else {
    for (int k = 0; k < cnt[2]; ++k)
      for (int j = 0; j < cnt[1]; ++j)
        for (int i = 0; i < cnt[0]; ++i)
          f(off[0][i] + off[1][j] + off[2][k]);
  }
}

// ---------------------------------------------------------------------------------------
// Predictions

template <int dim>
double HardSphereMD<dim>::pair_time(const Vec<dim>& xi, const Vec<dim>& vi, double rbi,
                                    int k) const {
  const State& sk = st_[k];
  const Vec<dim> dv = sk.v - vi;
  Vec<dim> dr = sk.x + (t_now_ - sk.t) * sk.v - xi;
  min_image(dr);
  const double rsum = rbi + sk.rb;
  const double sig = rsum * g_now_;
  const double sigd = rsum * rate_;
  const double rv = dr.dot(dv);
  const double b = rv - sig * sigd;
  const double a = dv.squaredNorm() - sigd * sigd;
  if (b >= 0.0 && a >= 0.0)
    return kInf;
  const double r2 = dr.squaredNorm();
  const double c = r2 - sig * sig;
  const double touch_rate = c <= 0.0 ? rv - std::sqrt(r2) * sigd : 0.0;
  return t_now_ + first_contact(a, b, c, touch_rate);
}

template <int dim> double HardSphereMD<dim>::crossing_time(int i, std::int32_t& cross) const {
  if (nl_) {
    cross = 0;
    return shell_exit_time(i);
  }
  const State& s = st_[i];
  double best = kInf;
  for (int a = 0; a < dim; ++a) {
    const double v = s.v[a];
    double dt;
    if (v > 0) {
      const int up = cc_[i][a] + 1;
      const double face = up == ncross_[a] ? box_[a] : up * cw_[a];
      dt = (face - s.x[a]) / v;
    } else if (v < 0) {
      dt = (cc_[i][a] * cw_[a] - s.x[a]) / v;
    } else {
      continue;
    }
    if (dt < 0)
      dt = 0;
    if (dt < best) {
      best = dt;
      cross = 2 * a + (v > 0 ? 1 : 0);
    }
  }
  return s.t + best;
}

/// Puts the grains of the stencil cells (see for_stencil) except `skip` into cand_.
template <int dim>
int HardSphereMD<dim>::gather(const std::array<int, dim>& c, int fixed_axis, int fixed_coord,
                              int skip) {
  int n = 0;
  std::int32_t* out = cand_.data();
  for_stencil(c, fixed_axis, fixed_coord, [&](int cell) {
    const std::int32_t* mem = &members_[static_cast<std::size_t>(cell) * cap_];
    const int cnt = count_in_[cell];
    for (int m = 0; m < cnt; ++m) {
      out[n] = mem[m];
      n += mem[m] != skip;
    }
  });
  return n;
}

/// Earliest collision of the grain (xi at t_now_, vi, base radius rbi) with cand[0..n),
/// lowering `best` / setting `partner` when one is earlier. This is the hot loop, so the
/// cheap tests come first: a receding pair (and, with fixed radii, one whose collision
/// cannot beat the best found so far, t >= c / (-2b)) costs no square root or division.
/// Plain scalars: Eigen's 2+1 packets of a 3-vector, written one component at a time by the
/// minimum image, would stall on store forwarding.
template <int dim>
template <bool growing>
void HardSphereMD<dim>::best_collision(const Vec<dim>& xi, const Vec<dim>& vi, double rbi,
                                       const std::int32_t* cand, int n, double& best,
                                       int& partner) const {
  const double g = g_now_, rate = rate_, t_now = t_now_;
  double x0[dim], v0[dim], h[dim], l[dim];
  for (int a = 0; a < dim; ++a) {
    x0[a] = xi[a];
    v0[a] = vi[a];
    h[a] = half_box_[a];
    l[a] = box_[a];
  }
  double t_best = best;
  int k_best = -1;
  for (int q = 0; q < n; ++q) {
    const State& sk = st_[cand[q]];
    const double dtk = t_now - sk.t;
    double rv = 0, r2 = 0, v2 = 0;
    for (int a = 0; a < dim; ++a) {
      double d = sk.x[a] + dtk * sk.v[a] - x0[a];
      d = d > h[a] ? d - l[a] : (d < -h[a] ? d + l[a] : d);
      const double w = sk.v[a] - v0[a];
      rv += d * w;
      r2 += d * d;
      v2 += w * w;
    }
    const double rsum = rbi + sk.rb;
    const double sig = rsum * g;
    double dt;
    if constexpr (!growing) {
      if (rv >= 0.0)
        continue;
      const double c = r2 - sig * sig;
      if (c > -2.0 * rv * (t_best - t_now))
        continue;
      // disc < 0: the pair misses. Else t = c / (-b + sqrt(disc)), which is <= 0, i.e. now,
      // for a touching or slightly overlapping pair.
      const double disc = rv * rv - v2 * c;
      if (disc < 0.0)
        continue;
      dt = std::max(c / (std::sqrt(disc) - rv), 0.0);
    } else {
      const double sigd = rsum * rate;
      const double b = rv - sig * sigd;
      const double a = v2 - sigd * sigd;
      if (b >= 0.0 && a >= 0.0)
        continue;
      const double c = r2 - sig * sig;
      if (a >= 0.0 && c > -2.0 * b * (t_best - t_now))
        continue; // disc <= b^2 here
      dt = first_contact(a, b, c, c <= 0.0 ? rv - std::sqrt(r2) * sigd : 0.0);
    }
    if (t_now + dt < t_best) {
      t_best = t_now + dt;
      k_best = cand[q];
    }
  }
  if (k_best >= 0) {
    best = t_best;
    partner = k_best;
  }
}

/// Predicts grain i against cand[0..n): its slot gets the earliest collision found, or, with
/// `keep`, only if it is earlier than the one it holds.
template <int dim> void HardSphereMD<dim>::scan(int i, const std::int32_t* cand, int n, bool keep) {
  const State& si = st_[i];
  const Vec<dim> xi = si.x + (t_now_ - si.t) * si.v;
  Slot& s = slots_[i];
  double best = keep ? s.t_coll : kInf;
  int partner = -1;
  if (rate_ != 0.0)
    best_collision<true>(xi, si.v, si.rb, cand, n, best, partner);
  else
    best_collision<false>(xi, si.v, si.rb, cand, n, best, partner);
  if (!keep || partner >= 0) {
    s.t_coll = best;
    s.partner = partner;
    s.partner_count = partner >= 0 ? count_[partner] : 0;
  }
}

template <int dim> void HardSphereMD<dim>::scan_full(int i) {
  if (nl_) {
    scan(i, &nb_[static_cast<std::size_t>(i) * nb_cap_], nb_count_[i], false);
  } else {
    const int n = gather(cc_[i], -1, 0, i);
    scan(i, cand_.data(), n, false);
  }
}

template <int dim> void HardSphereMD<dim>::scan_slab(int i, int axis, int coord) {
  const int n = gather(cc_[i], axis, coord, i);
  scan(i, cand_.data(), n, true);
}

template <int dim> void HardSphereMD<dim>::predict_all() {
  const int n = static_cast<int>(st_.size());
  for (int i = 0; i < n; ++i) {
    Slot& s = slots_[i];
    s.t_coll = kInf;
    s.partner = -1;
    s.t_cross = crossing_time(i, s.cross);
  }
  // Each pair once (k > i), offered to both grains' slots.
  for (int i = 0; i < n; ++i) {
    const State& si = st_[i];
    const Vec<dim> xi = si.x + (t_now_ - si.t) * si.v;
    Slot& s = slots_[i];
    auto offer = [&](int k) {
      if (k <= i)
        return;
      const double t = pair_time(xi, si.v, si.rb, k);
      if (t < s.t_coll) {
        s.t_coll = t;
        s.partner = k;
        s.partner_count = count_[k];
      }
      Slot& sk = slots_[k];
      if (t < sk.t_coll) {
        sk.t_coll = t;
        sk.partner = i;
        sk.partner_count = count_[i];
      }
    };
    if (nl_) {
      const std::int32_t* nb = &nb_[static_cast<std::size_t>(i) * nb_cap_];
      for (int m = 0; m < nb_count_[i]; ++m)
        offer(nb[m]);
    } else {
      for_stencil(cc_[i], -1, 0, [&](int c) {
        const std::int32_t* mem = &members_[static_cast<std::size_t>(c) * cap_];
        for (int m = 0; m < count_in_[c]; ++m)
          offer(mem[m]);
      });
    }
  }
  heap_build();
  calendar_ok_ = true;
}

// ---------------------------------------------------------------------------------------
// Calendar: binary min-heap of one event per grain, keyed by time, with positions where_.

template <int dim> void HardSphereMD<dim>::heap_build() {
  const std::size_t n = st_.size();
  heap_.resize(n);
  where_.resize(n);
  for (std::size_t p = 0; p < n; ++p) {
    heap_[p] = HeapNode{key(static_cast<int>(p)), static_cast<std::int32_t>(p)};
    where_[p] = static_cast<std::int32_t>(p);
  }
  for (std::size_t p = n / 2; p-- > 0;)
    sift_down(p);
}

template <int dim> void HardSphereMD<dim>::sift_up(std::size_t p) {
  const HeapNode node = heap_[p];
  while (p > 0) {
    const std::size_t parent = (p - 1) / 2;
    if (!(node.t < heap_[parent].t))
      break;
    heap_[p] = heap_[parent];
    where_[heap_[p].id] = static_cast<std::int32_t>(p);
    p = parent;
  }
  heap_[p] = node;
  where_[node.id] = static_cast<std::int32_t>(p);
}

template <int dim> void HardSphereMD<dim>::sift_down(std::size_t p) {
  const HeapNode node = heap_[p];
  const std::size_t n = heap_.size();
  for (;;) {
    std::size_t m = 2 * p + 1;
    if (m >= n)
      break;
    if (m + 1 < n && heap_[m + 1].t < heap_[m].t)
      ++m;
    if (!(heap_[m].t < node.t))
      break;
    heap_[p] = heap_[m];
    where_[heap_[p].id] = static_cast<std::int32_t>(p);
    p = m;
  }
  heap_[p] = node;
  where_[node.id] = static_cast<std::int32_t>(p);
}

template <int dim> void HardSphereMD<dim>::heap_update(int i) {
  const std::size_t p = static_cast<std::size_t>(where_[i]);
  const double t = key(i);
  const double old = heap_[p].t;
  heap_[p].t = t;
  if (t < old)
    sift_up(p);
  else
    sift_down(p);
}

// ---------------------------------------------------------------------------------------
// Neighbour lists (fixed radii): Donev, Torquato & Stillinger, J. Comput. Phys. 202 (2005)
// 737; Smallenburg, arXiv:2201.01231 (2022). A grain's list holds every grain whose list
// centre is closer than the sum of radii + 2 h to its own; while each grain stays within h of
// its centre, a pair outside the lists cannot touch. Leaving the sphere of radius h around its
// centre is an event ("shell exit", in place of the cell crossings): the grain takes its
// position as its new centre and rebuilds its list from the cells (which hold the centres).

template <int dim> bool HardSphereMD<dim>::nl_possible() const {
  if (rate_ != 0.0)
    return false;
  double rmax = 0;
  for (const State& s : st_)
    rmax = std::max(rmax, s.rb);
  const double side = 2 * rmax * (1 + 2 * kShell) * (1 + kCellMargin);
  for (int a = 0; a < dim; ++a)
    if (std::floor(box_[a] / side) < 4)
      return false;
  return true;
}

template <int dim> void HardSphereMD<dim>::nl_build() {
  move_all_to_now();
  double rmax = 0;
  for (const State& s : st_)
    rmax = std::max(rmax, s.rb);
  shell_ = 2 * rmax * kShell;
  build_cells(2 * rmax + 2 * shell_); // wraps the positions into [0, L)
  const int n = static_cast<int>(st_.size());
  ctr_.resize(st_.size());
  for (int i = 0; i < n; ++i)
    ctr_[i] = st_[i].x;
  nb_cap_ = 32;
  nb_count_.assign(st_.size(), 0);
  nb_.assign(st_.size() * nb_cap_, -1);
  for (int i = 0; i < n; ++i)
    nl_link(i, i);
  nl_ = true;
}

/// Links grain i with every grain k > `above` (k != i) whose centre is within the list range.
template <int dim> void HardSphereMD<dim>::nl_link(int i, int above) {
  const Vec<dim> x0 = ctr_[i];
  const double ri = st_[i].rb + 2 * shell_;
  for_stencil(cc_[i], -1, 0, [&](int c) {
    const std::int32_t* mem = &members_[static_cast<std::size_t>(c) * cap_];
    for (int m = 0; m < count_in_[c]; ++m) {
      const int k = mem[m];
      if (k <= above || k == i)
        continue;
      Vec<dim> d = ctr_[k] - x0;
      min_image(d);
      const double lim = (ri + st_[k].rb) * (1 + kCellMargin);
      if (d.squaredNorm() < lim * lim)
        nl_add(i, k);
    }
  });
}

template <int dim> void HardSphereMD<dim>::nl_add(int i, int k) {
  if (nb_count_[i] == nb_cap_ || nb_count_[k] == nb_cap_)
    double_row_capacity(nb_, nb_cap_, nb_count_);
  nb_[static_cast<std::size_t>(i) * nb_cap_ + nb_count_[i]++] = k;
  nb_[static_cast<std::size_t>(k) * nb_cap_ + nb_count_[k]++] = i;
}

/// Removes grain i from the lists of its neighbours and empties its own.
template <int dim> void HardSphereMD<dim>::nl_unlink(int i) {
  const std::int32_t* nb = &nb_[static_cast<std::size_t>(i) * nb_cap_];
  for (int m = 0; m < nb_count_[i]; ++m) {
    const int k = nb[m];
    std::int32_t* nk = &nb_[static_cast<std::size_t>(k) * nb_cap_];
    const int last = --nb_count_[k];
    int q = 0;
    while (nk[q] != i)
      ++q;
    nk[q] = nk[last];
  }
  nb_count_[i] = 0;
}

/// Time at which grain i leaves the sphere of radius h around its list centre.
template <int dim> double HardSphereMD<dim>::shell_exit_time(int i) const {
  const State& s = st_[i];
  const Vec<dim> p = s.x - ctr_[i];
  const double a = s.v.squaredNorm();
  if (!(a > 0))
    return kInf;
  const double b = p.dot(s.v);
  const double c = p.squaredNorm() - shell_ * shell_;
  if (c >= 0)
    return s.t; // on the sphere (round-off): rebuild now
  const double q = std::sqrt(b * b - a * c);
  return s.t + (b >= 0 ? -c / (b + q) : (q - b) / a);
}

/// Shell exit of grain i (moved to now): new centre, new list, full re-prediction.
template <int dim> void HardSphereMD<dim>::nl_rebuild(int i) {
  State& s = st_[i];
  for (int a = 0; a < dim; ++a)
    s.x[a] = wrap(s.x[a], box_[a]);
  nl_unlink(i);
  ctr_[i] = s.x;
  std::array<int, dim>& c = cc_[i];
  for (int a = 0; a < dim; ++a)
    c[a] = std::clamp(static_cast<int>(std::floor(s.x[a] / cw_[a])), 0, ncross_[a] - 1);
  const int cell = flat(c);
  if (cell != cell_of_[i]) {
    cell_remove(i);
    cell_insert(i, cell);
  }
  nl_link(i, -1);
  scan_full(i);
  Slot& sl = slots_[i];
  sl.t_cross = shell_exit_time(i);
  heap_update(i);
}

// ---------------------------------------------------------------------------------------
// Events

template <int dim> void HardSphereMD<dim>::move_to_now(int i) {
  State& s = st_[i];
  s.x += (t_now_ - s.t) * s.v;
  s.t = t_now_;
}

template <int dim> void HardSphereMD<dim>::move_all_to_now() {
  for (int i = 0; i < static_cast<int>(st_.size()); ++i)
    move_to_now(i);
}

template <int dim> void HardSphereMD<dim>::process_crossing(int i) {
  move_to_now(i);
  if (nl_) {
    nl_rebuild(i);
    return;
  }
  Slot& s = slots_[i];
  const int a = s.cross >> 1;
  const bool up = (s.cross & 1) != 0;
  State& st = st_[i];
  std::array<int, dim>& c = cc_[i];
  if (up) {
    if (++c[a] == ncross_[a]) {
      c[a] = 0;
      st.x[a] -= box_[a];
    }
  } else if (--c[a] < 0) {
    c[a] = ncross_[a] - 1;
    st.x[a] += box_[a];
  }
  if (real_[a]) {
    // New neighbours: the layer of cells beyond the new cell; the old prediction stays (if
    // its partner has collided since, it is stale and will be re-predicted when popped).
    cell_remove(i);
    cell_insert(i, flat(c));
    const int n = ncross_[a];
    const int layer = up ? (c[a] + 1 == n ? 0 : c[a] + 1) : (c[a] == 0 ? n - 1 : c[a] - 1);
    scan_slab(i, a, layer);
  } else {
    scan_full(i);
  }
  s.t_cross = crossing_time(i, s.cross);
  heap_update(i);
}

template <int dim> void HardSphereMD<dim>::process_collision(int i, int j) {
  move_to_now(i);
  move_to_now(j);
  State& si = st_[i];
  State& sj = st_[j];
  Vec<dim> dr = sj.x - si.x;
  min_image(dr);
  const double dist = dr.norm();
  const Vec<dim> nrm = dr / dist;
  const double vn = (sj.v - si.v).dot(nrm);
  const double sigd = (si.rb + sj.rb) * rate_;
  // Reflect the normal velocity relative to the growing contact: vn' - sigd = -(vn - sigd).
  double dvn = 2 * (sigd - vn);
  if (!(dvn > 0))
    dvn = 0; // grazing within round-off: nothing to transfer
  const double mi = mass_[i], mj = mass_[j];
  const double impulse = dvn / (inv_mass_[i] + inv_mass_[j]);
  const double k_before = 0.5 * (mi * si.v.squaredNorm() + mj * sj.v.squaredNorm());
  si.v -= (impulse * inv_mass_[i]) * nrm;
  sj.v += (impulse * inv_mass_[j]) * nrm;
  const double k_after = 0.5 * (mi * si.v.squaredNorm() + mj * sj.v.squaredNorm());
  accumulate_kinetic();
  k_track_ += k_after - k_before;
  virial_ += dist * impulse;
  ++count_[i];
  ++count_[j];
  ++n_collisions_;
  scan_full(i);
  scan_full(j);
  slots_[i].t_cross = crossing_time(i, slots_[i].cross);
  slots_[j].t_cross = crossing_time(j, slots_[j].cross);
  heap_update(i);
  heap_update(j);
}

/// Processes events in time order up to t_stop (inclusive) or until max_collisions
/// collisions; returns the number of collisions. The clock is left at the last event.
template <int dim>
std::int64_t HardSphereMD<dim>::advance(double t_stop, std::int64_t max_collisions) {
  std::int64_t done = 0;
  while (done < max_collisions) {
    const HeapNode top = heap_[0];
    if (!(top.t <= t_stop) || top.t == kInf)
      break;
    set_time(top.t);
    const int i = top.id;
    const Slot& s = slots_[i];
    if (s.t_cross <= s.t_coll) {
      process_crossing(i);
    } else if (count_[s.partner] != s.partner_count) {
      scan_full(i); // the partner changed course since the prediction
      heap_update(i);
    } else {
      process_collision(i, s.partner);
      ++done;
    }
  }
  return done;
}

template <int dim> void HardSphereMD<dim>::ensure_calendar() {
  if (calendar_ok_)
    return;
  if (!nl_ && nl_possible())
    nl_build();
  predict_all();
}

// ---------------------------------------------------------------------------------------
// Runs

template <int dim> void HardSphereMD<dim>::run_collisions(std::int64_t n) {
  GRANPACK_CHECK(n >= 0, "HardSphereMD::run_collisions: negative count " << n);
  ensure_calendar();
  const std::int64_t done = advance(kInf, n);
  sync_output();
  GRANPACK_CHECK(done == n, "HardSphereMD::run_collisions: only "
                                << done << " of " << n
                                << " collisions: no further collision is predicted");
}

template <int dim> void HardSphereMD<dim>::run_for(double duration) {
  GRANPACK_CHECK(std::isfinite(duration) && duration >= 0,
                 "HardSphereMD::run_for: duration " << duration);
  ensure_calendar();
  const double t_stop = t_now_ + duration;
  advance(t_stop, std::numeric_limits<std::int64_t>::max());
  set_time(t_stop);
  sync_output();
}

template <int dim>
void HardSphereMD<dim>::grow(double phi_target, double rate, double rescale_every,
                             std::function<void(const HardSphereMD&)> progress) {
  begin_growth(phi_target, rate, rescale_every);
  while (!continue_growth(std::numeric_limits<std::int64_t>::max(), progress)) {
  }
}

template <int dim>
void HardSphereMD<dim>::begin_growth(double phi_target, double rate, double rescale_every) {
  GRANPACK_CHECK(std::isfinite(rate) && rate > 0, "HardSphereMD::grow: rate " << rate);
  GRANPACK_CHECK(std::isfinite(rescale_every) && rescale_every > 0,
                 "HardSphereMD::grow: rescale_every " << rescale_every);
  const double phi0 = solid_fraction();
  GRANPACK_CHECK(std::isfinite(phi_target) && phi_target >= phi0,
                 "HardSphereMD::grow: target solid fraction " << phi_target
                                                              << " is below the current " << phi0);
  growth_ = Growth{};
  if (phi_target == phi0)
    return;
  Growth& g = growth_;
  g.phi_target = phi_target;
  g.k0 = kinetic_energy();
  GRANPACK_CHECK(g.k0 > 0, "HardSphereMD::grow: the grains are at rest (kinetic energy 0)");
  g.g_end = std::pow(phi_target / phi0, 1.0 / dim);
  for (const State& s : st_)
    g.rb_max = std::max(g.rb_max, s.rb);
  g.d_final = 2 * g.rb_max * g.g_end;
  for (int a = 0; a < dim; ++a)
    GRANPACK_CHECK(0.5 * box_[a] > g.d_final * (1 + 2 * kCellMargin),
                   "HardSphereMD::grow: at solid fraction "
                       << phi_target << " the largest diameter " << g.d_final
                       << " would not fit twice in the box length " << box_[a]);

  double mass = 0;
  for (std::size_t i = 0; i < st_.size(); ++i) {
    mass += mass_[i];
    g.rb_mean += st_[i].rb;
  }
  g.rb_mean /= static_cast<double>(st_.size());
  g.v_rms = std::sqrt(2 * g.k0 / mass);

  // Growth origin: radii r = rb (1 + rate (t - t0)).
  t0_ = t_now_;
  rate_ = rate;
  g_now_ = 1.0;
  g.t_end = t0_ + (g.g_end - 1.0) / rate;
  const auto n = static_cast<std::int64_t>(st_.size());
  g.rescale_n = std::max<std::int64_t>(1, std::llround(rescale_every * static_cast<double>(n)));
  g.progress_n = n;
  g.t_window = t_now_;
  g.active = true;
  growth_rebuild();
}

/// Back to fixed radii rb g at the current time.
template <int dim> void HardSphereMD<dim>::growth_freeze(double g) {
  move_all_to_now();
  for (State& s : st_)
    s.rb *= g;
  rate_ = 0;
  t0_ = t_now_;
  g_now_ = 1.0;
  calendar_ok_ = false;
  growth_.active = false;
  accumulate_kinetic();
  sync_output();
}

template <int dim> void HardSphereMD<dim>::growth_rebuild() {
  move_all_to_now();
  build_cells(std::min(growth_.d_final, 2 * growth_.rb_max * g_now_ * (1 + kGrowthHeadroom)));
  predict_all();
}

template <int dim>
bool HardSphereMD<dim>::continue_growth(std::int64_t max_collisions,
                                        const std::function<void(const HardSphereMD&)>& progress) {
  Growth& g = growth_;
  const auto n = static_cast<std::int64_t>(st_.size());
  std::int64_t budget = max_collisions;
  // The top of this loop is the only place a piece ends: what follows advance() is done.
  while (g.active && budget > 0) {
    // The grid holds while the largest diameter 2 rb_max g(t) <= d_lim_.
    const double t_lim = d_lim_ == kInf ? kInf : t0_ + (d_lim_ / (2 * g.rb_max) - 1.0) / rate_;
    const double t_stop = std::min(t_lim, g.t_end);
    const std::int64_t batch =
        std::min({g.rescale_n - g.since_rescale, g.progress_n - g.since_progress,
                  n - g.since_window, budget});
    const std::int64_t done = advance(t_stop, batch);
    budget -= done;
    g.since_rescale += done;
    g.since_progress += done;
    g.since_window += done;
    if (g.since_rescale >= g.rescale_n) {
      move_all_to_now();
      const double k = kinetic_energy();
      if (k > 0) {
        const double f = std::sqrt(g.k0 / k);
        for (State& s : st_)
          s.v *= f;
      }
      accumulate_kinetic();
      k_track_ = kinetic_energy();
      predict_all();
      g.since_rescale = 0;
    }
    if (g.since_progress >= g.progress_n) {
      if (progress) {
        sync_output();
        progress(*this);
      }
      g.since_progress = 0;
    }
    if (g.since_window >= n) {
      const bool stuck = g.v_rms * (t_now_ - g.t_window) < kStallPath * 2 * g.rb_mean * g_now_;
      g.stalled = stuck ? g.stalled + 1 : 0;
      g.since_window = 0;
      g.t_window = t_now_;
      if (g.stalled >= kStallWindows) {
        const double target = g.phi_target;
        growth_freeze(g_now_);
        std::ostringstream os;
        os << "HardSphereMD::grow: jammed at solid fraction " << solid_fraction()
           << " below the target " << target
           << " (the time stopped advancing; a slower growth rate packs denser)";
        throw Error(os.str());
      }
    }
    if (done < batch) { // reached t_stop
      set_time(t_stop);
      if (t_stop >= g.t_end) {
        // Stop exactly at the target: freeze the radii at rb g_end.
        growth_freeze(g.g_end);
        break;
      }
      growth_rebuild();
    }
  }
  return !g.active;
}

template class HardSphereMD<2>;
template class HardSphereMD<3>;

} // namespace granpack
