// Saving and restoring the complete state of the event-driven engine (HardSphereMD::
// save_state / restore_state), for checkpoints inside the ed_gas and ls_compress stages.
//
// Why everything, and not just positions and velocities: grains carry their own clocks, and
// the calendar, the per-grain collision counters (which mark stale predictions) and the order
// of the grains inside each cell (which decides exact ties) all shape the next events.
// Rebuilding them from synchronised positions would be deterministic, but it moves every
// grain to the common time (new rounding) and re-predicts every event, so the continued run
// would differ in the last bits from a run that never stopped. Saved whole, the restored
// engine is the same machine, and a checkpoint may be taken at any instant (a signal, the
// wall clock) without changing the trajectory.
#include <cstring>
#include <sstream>
#include <type_traits>

#include "granpack/core/error.h"
#include "granpack/dynamics/hard_sphere_md.h"

namespace granpack {

namespace {

// Version 02 adds the neighbour lists; a version 01 state (no lists) is still read.
constexpr char kMagic[8] = {'G', 'P', 'H', 'S', 'M', 'D', '0', '2'};

class Writer {
public:
  template <class T> void pod(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    const auto* p = reinterpret_cast<const std::uint8_t*>(&v);
    out.insert(out.end(), p, p + sizeof(T));
  }
  template <class T> void vec(const std::vector<T>& v) {
    pod(static_cast<std::uint64_t>(v.size()));
    for (const T& x : v)
      pod(x);
  }
  template <int n> void vec(const Vec<n>& v) {
    for (int a = 0; a < n; ++a)
      pod(v[a]);
  }
  std::vector<std::uint8_t> out;
};

class Reader {
public:
  explicit Reader(const std::vector<std::uint8_t>& in) : in_(in) {}
  template <class T> T pod() {
    static_assert(std::is_trivially_copyable_v<T>);
    if (in_.size() - pos_ < sizeof(T))
      fail("it ends early");
    T v;
    std::memcpy(&v, in_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  /// A vector of `expected` elements (any count if expected < 0).
  template <class T> std::vector<T> vec(std::int64_t expected, const char* what) {
    const auto n = pod<std::uint64_t>();
    if ((expected >= 0 && n != static_cast<std::uint64_t>(expected)) ||
        n > (in_.size() - pos_) / sizeof(T))
      fail(std::string(what) + " has " + std::to_string(n) + " entries");
    std::vector<T> v(static_cast<std::size_t>(n));
    for (auto& x : v)
      x = pod<T>();
    return v;
  }
  template <int n> Vec<n> vecd() {
    Vec<n> v;
    for (int a = 0; a < n; ++a)
      v[a] = pod<double>();
    return v;
  }
  bool at_end() const { return pos_ == in_.size(); }
  [[noreturn]] static void fail(const std::string& why) {
    throw Error("not a saved state of the event-driven engine: " + why);
  }

private:
  const std::vector<std::uint8_t>& in_;
  std::size_t pos_ = 0;
};

bool in_range(std::int64_t v, std::int64_t lo, std::int64_t hi) {
  return v >= lo && v < hi;
}

} // namespace

template <int dim> std::vector<std::uint8_t> HardSphereMD<dim>::save_state() const {
  Writer w;
  for (char c : kMagic)
    w.pod(c);
  w.pod(static_cast<std::int32_t>(dim));
  w.vec(box_);
  w.pod(static_cast<std::uint64_t>(st_.size()));
  for (const State& s : st_) {
    w.vec(s.x);
    w.pod(s.t);
    w.vec(s.v);
    w.pod(s.rb);
  }
  w.vec(mass_);
  w.vec(count_);
  w.vec(slots_);
  w.vec(heap_);
  w.vec(where_);
  w.pod(ncross_);
  w.pod(real_);
  w.pod(stride_);
  w.vec(cw_);
  w.pod(d_lim_);
  w.pod(static_cast<std::int32_t>(cap_));
  w.vec(count_in_);
  // Of a table of fixed-capacity rows only the occupied entries: their order within a row
  // matters, the rest is unused (the cells' members, the neighbour lists).
  auto occupied_rows = [&w](const std::vector<std::int32_t>& rows, int cap,
                            const std::vector<std::int32_t>& count) {
    for (std::size_t r = 0; r < count.size(); ++r)
      for (int m = 0; m < count[r]; ++m)
        w.pod(rows[r * cap + m]);
  };
  occupied_rows(members_, cap_, count_in_);
  w.vec(cell_of_);
  w.vec(slot_in_cell_);
  w.vec(cc_);
  w.pod(t_now_);
  w.pod(t0_);
  w.pod(rate_);
  w.pod(g_now_);
  w.pod(calendar_ok_);
  w.pod(n_collisions_);
  w.pod(t_press0_);
  w.pod(virial_);
  w.pod(kin_integral_);
  w.pod(k_track_);
  w.pod(t_kin_);
  w.pod(growth_);
  w.pod(nl_);
  if (nl_) {
    w.pod(shell_);
    for (const Vec<dim>& c : ctr_)
      w.vec(c);
    w.pod(static_cast<std::int32_t>(nb_cap_));
    w.vec(nb_count_);
    occupied_rows(nb_, nb_cap_, nb_count_);
  }
  return std::move(w.out);
}

template <int dim>
HardSphereMD<dim> HardSphereMD<dim>::restore_state(const std::vector<std::uint8_t>& state) {
  Reader r(state);
  bool v1 = false;
  for (int k = 0; k < 8; ++k) {
    const char c = r.pod<char>();
    if (k == 7 && c == '1')
      v1 = true;
    else if (c != kMagic[k])
      Reader::fail("wrong signature");
  }
  if (r.pod<std::int32_t>() != dim)
    Reader::fail("saved by an engine of another dimension");
  HardSphereMD md;
  md.box_ = r.vecd<dim>();
  md.half_box_ = 0.5 * md.box_;
  const auto n64 = r.pod<std::uint64_t>();
  if (n64 == 0 || n64 > static_cast<std::uint64_t>(std::numeric_limits<std::int32_t>::max()) ||
      n64 > state.size())
    Reader::fail(std::to_string(n64) + " grains");
  const auto n = static_cast<std::int64_t>(n64);
  md.st_.resize(static_cast<std::size_t>(n));
  for (State& s : md.st_) {
    s.x = r.vecd<dim>();
    s.t = r.pod<double>();
    s.v = r.vecd<dim>();
    s.rb = r.pod<double>();
  }
  md.mass_ = r.vec<double>(n, "the mass array");
  md.inv_mass_.resize(md.mass_.size());
  for (std::size_t i = 0; i < md.mass_.size(); ++i)
    md.inv_mass_[i] = 1.0 / md.mass_[i];
  md.count_ = r.vec<std::uint64_t>(n, "the collision counters");
  md.slots_ = r.vec<Slot>(n, "the calendar slots");
  // The calendar is built by the first run (empty before it).
  md.heap_ = r.vec<HeapNode>(-1, "the calendar heap");
  md.where_ = r.vec<std::int32_t>(-1, "the heap positions");
  const bool heap = !md.heap_.empty();
  if ((heap && md.heap_.size() != md.st_.size()) || md.where_.size() != md.heap_.size())
    Reader::fail("a calendar of " + std::to_string(md.heap_.size()) + " entries");
  md.ncross_ = r.pod<std::array<int, dim>>();
  md.real_ = r.pod<std::array<bool, dim>>();
  md.stride_ = r.pod<std::array<int, dim>>();
  md.cw_ = r.vecd<dim>();
  md.d_lim_ = r.pod<double>();
  md.cap_ = r.pod<std::int32_t>();
  std::int64_t cells = 1;
  for (int a = 0; a < dim; ++a) {
    if (md.ncross_[a] < 1 || md.ncross_[a] > 100000000)
      Reader::fail("a bad cell grid");
    if (md.real_[a])
      cells *= md.ncross_[a];
  }
  if (cells >= (1L << 30) || md.cap_ < 1 || md.cap_ > n + 8)
    Reader::fail("a bad cell grid");
  md.count_in_ = r.vec<std::int32_t>(cells, "the cell occupation");
  md.members_.assign(static_cast<std::size_t>(cells) * md.cap_, -1);
  std::int64_t members = 0;
  for (std::int64_t c = 0; c < cells; ++c) {
    const int k = md.count_in_[c];
    if (!in_range(k, 0, md.cap_ + 1))
      Reader::fail("a cell with " + std::to_string(k) + " grains");
    members += k;
    for (int m = 0; m < k; ++m) {
      const auto i = r.pod<std::int32_t>();
      if (!in_range(i, 0, n))
        Reader::fail("a cell member out of range");
      md.members_[c * md.cap_ + m] = i;
    }
  }
  if (members != n)
    Reader::fail("the cells hold " + std::to_string(members) + " grains");
  md.cell_of_ = r.vec<std::int32_t>(n, "the cell of each grain");
  md.slot_in_cell_ = r.vec<std::int32_t>(n, "the slot of each grain");
  md.cc_ = r.vec<std::array<int, dim>>(n, "the slab coordinates");
  for (std::int64_t i = 0; i < n; ++i) {
    const Slot& s = md.slots_[i];
    if (!in_range(md.cell_of_[i], 0, cells) || !in_range(md.slot_in_cell_[i], 0, md.cap_) ||
        md.members_[md.cell_of_[i] * md.cap_ + md.slot_in_cell_[i]] != i ||
        !in_range(s.partner, -1, n) ||
        (heap && (!in_range(md.heap_[i].id, 0, n) || !in_range(md.where_[i], 0, n) ||
                  md.heap_[md.where_[i]].id != i)))
      Reader::fail("inconsistent indices at grain " + std::to_string(i));
    for (int a = 0; a < dim; ++a)
      if (!in_range(md.cc_[i][a], 0, md.ncross_[a]))
        Reader::fail("a slab coordinate out of range");
  }
  md.cand_.resize(static_cast<std::size_t>(n));
  md.t_now_ = r.pod<double>();
  md.t0_ = r.pod<double>();
  md.rate_ = r.pod<double>();
  md.g_now_ = r.pod<double>();
  md.calendar_ok_ = r.pod<bool>();
  if (md.calendar_ok_ && !heap)
    Reader::fail("a valid calendar without entries");
  md.n_collisions_ = r.pod<std::int64_t>();
  md.t_press0_ = r.pod<double>();
  md.virial_ = r.pod<double>();
  md.kin_integral_ = r.pod<double>();
  md.k_track_ = r.pod<double>();
  md.t_kin_ = r.pod<double>();
  md.growth_ = r.pod<Growth>();
  md.nl_ = !v1 && r.pod<bool>();
  if (md.nl_) {
    md.shell_ = r.pod<double>();
    md.ctr_.resize(static_cast<std::size_t>(n));
    for (auto& c : md.ctr_)
      c = r.vecd<dim>();
    md.nb_cap_ = r.pod<std::int32_t>();
    if (md.nb_cap_ < 1 || md.nb_cap_ > n + 32)
      Reader::fail("a bad neighbour list capacity");
    md.nb_count_ = r.vec<std::int32_t>(n, "the neighbour counts");
    md.nb_.assign(static_cast<std::size_t>(n) * md.nb_cap_, -1);
    for (std::int64_t i = 0; i < n; ++i) {
      if (!in_range(md.nb_count_[i], 0, md.nb_cap_ + 1))
        Reader::fail("a neighbour list of " + std::to_string(md.nb_count_[i]) + " grains");
      for (int m = 0; m < md.nb_count_[i]; ++m) {
        const auto k = r.pod<std::int32_t>();
        if (!in_range(k, 0, n) || k == i)
          Reader::fail("a neighbour out of range");
        md.nb_[i * md.nb_cap_ + m] = k;
      }
    }
  }
  if (!r.at_end())
    Reader::fail("trailing bytes");
  md.out_pos_.resize(md.st_.size());
  md.out_vel_.resize(md.st_.size());
  md.out_radii_.resize(md.st_.size());
  md.sync_output();
  return md;
}

template std::vector<std::uint8_t> HardSphereMD<2>::save_state() const;
template std::vector<std::uint8_t> HardSphereMD<3>::save_state() const;
template HardSphereMD<2> HardSphereMD<2>::restore_state(const std::vector<std::uint8_t>&);
template HardSphereMD<3> HardSphereMD<3>::restore_state(const std::vector<std::uint8_t>&);

} // namespace granpack
