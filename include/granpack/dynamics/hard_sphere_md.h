#pragma once
// Event-driven molecular dynamics (EDMD) of hard spheres (3D) or disks (2D) in a periodic
// orthorhombic cell, with Lubachevsky-Stillinger (LS) growth of the radii.
//
// Why event-driven: between collisions hard spheres fly straight, so the exact dynamics is a
// sequence of binary collisions found by solving quadratics; there is no time step and no
// overlap. LS growth turns this into a packing generator: all radii grow linearly in time
// while the grains keep colliding, which spreads the free volume and keeps the packing
// disordered (docs/event-driven.md says what is done and where the limits are).
//
// Algorithm (docs/event-driven.md):
// - particles carry their own clock (position at a local time t_i); a collision or a
//   cell crossing advances only the grains involved;
// - a periodic cell list (side >= largest diameter), each cell a small contiguous array;
//   along an axis that fits fewer than 4 cells the whole axis is one cell (all pairs), and
//   grains re-predict after every (L/2 - d)/2 of travel along it so the minimum image of a
//   pair cannot switch unnoticed;
// - at fixed radii (and >= 4 cells of side d_max (1 + 2 * 0.25) per axis) neighbour lists
//   instead: each grain is predicted only against the grains whose list centres are closer
//   than r_i + r_j + 2h, and leaving the sphere of radius h around its own centre (a "shell
//   exit", in place of the cell crossings) rebuilds its list;
// - the calendar holds ONE event per grain (the earlier of its best collision and its next
//   cell crossing) in an indexed binary heap; a collision prediction stores the partner's
//   collision counter, and is recognised as stale (and re-predicted) when popped if that
//   partner collided in the meantime;
// - growing contact distance sigma(t) = sigma0 + sigma' t: |r + v t| = sigma(t) is a
//   quadratic, solved in the cancellation-free form.
//
// MPI-free (granpack_physics). Errors throw granpack::Error.
#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

#include "granpack/core/vec.h"

namespace granpack {

template <int dim> class HardSphereMD {
public:
  /// box: orthorhombic periodic cell lengths (real units). positions in real coordinates
  /// (any values; wrapped into [0,L) internally), radii > 0, masses > 0, velocities.
  /// Throws granpack::Error if two spheres overlap by more than 1e-9 of the sum of radii
  /// (smaller overlaps are treated as contact: an approaching pair collides at once), or if
  /// a box length is not larger than two largest diameters (minimum image).
  HardSphereMD(const Vec<dim>& box, std::vector<Vec<dim>> positions, std::vector<double> radii,
               std::vector<double> masses, std::vector<Vec<dim>> velocities);

  /// Fixed volume, fixed radii, elastic collisions: advance until `n` more collisions happened
  /// (the clock stops at the n-th collision).
  void run_collisions(std::int64_t n);
  /// Fixed volume, fixed radii: advance the clock by `duration` (>= 0).
  void run_for(double duration);

  /// Lubachevsky-Stillinger growth: all radii grow as r_i(t) = r_i(t0) (1 + rate (t - t0))
  /// until the solid fraction reaches phi_target, where it stops exactly (no overlap). At a
  /// collision the normal relative velocity relative to the growing contact is reversed:
  /// v_n' = 2 sigma' - v_n with sigma' = d(r_i + r_j)/dt, i.e. the elastic value -v_n plus
  /// 2 sigma' (docs/event-driven.md: why not + sigma'), so the pair always separates. After
  /// every rescale_every * n collisions the velocities are rescaled so that the kinetic
  /// energy returns to its value at the start of grow() (which must be > 0). `progress` is
  /// called (positions synchronised) about every n collisions. Throws if phi_target is below
  /// the current solid fraction or if the final diameters would not fit the box (L > 2 d);
  /// also if the packing jams below phi_target (the clock stops advancing: the grains travel
  /// less than 1e-12 diameters in 3 n collisions), leaving the radii frozen where it jammed.
  void grow(double phi_target, double rate, double rescale_every = 1.0,
            std::function<void(const HardSphereMD&)> progress = {});
  /// grow() in pieces, so a caller can checkpoint or stop in the middle: begin_growth() makes
  /// grow()'s checks and set-up; then continue_growth() runs at most `max_collisions` more
  /// collisions and returns true once the target is reached (false: call it again). Pieces of
  /// any size give bit for bit the trajectory of one grow() call.
  void begin_growth(double phi_target, double rate, double rescale_every = 1.0);
  bool continue_growth(std::int64_t max_collisions,
                       const std::function<void(const HardSphereMD&)>& progress = {});
  bool growing() const { return growth_.active; }

  /// Everything the engine's future depends on, byte for byte: grains (positions at their
  /// own clocks, velocities, radii, masses, collision counters), the calendar, the cell list
  /// with its members' order, the clocks, counters, pressure accumulators and a growth in
  /// progress. An engine restored from it continues exactly as this one would have, so a
  /// checkpoint can be taken at any instant without changing the trajectory
  /// (docs/long-jobs.md). Binary, for this build's platform (little-endian doubles).
  std::vector<std::uint8_t> save_state() const;
  /// Throws granpack::Error if `state` is not a saved state of a dim-D engine.
  static HardSphereMD restore_state(const std::vector<std::uint8_t>& state);

  const std::vector<Vec<dim>>& positions() const { return out_pos_; } ///< wrapped into [0,L)
  const std::vector<Vec<dim>>& velocities() const { return out_vel_; }
  const std::vector<double>& radii() const { return out_radii_; }
  const std::vector<double>& masses() const { return mass_; }
  const Vec<dim>& box() const { return box_; }
  std::size_t size() const { return mass_.size(); }
  double time() const { return t_now_; }
  std::int64_t collisions() const { return n_collisions_; } ///< total since construction
  double kinetic_energy() const;                            ///< sum 1/2 m v^2
  Vec<dim> momentum() const;                                ///< sum m v
  double solid_fraction() const; ///< sum of sphere volumes (disk areas) / cell volume

  /// Collisional (virial) pressure averaged since the last reset_pressure() (or
  /// construction), including the kinetic part:
  ///   P = 2 <K> / (dim V) + (1 / (dim V t_acc)) sum_collisions r_ij . dp_ij,
  /// <K> the time-averaged kinetic energy, r_ij the centre separation at contact, dp_ij the
  /// momentum transferred (during LS growth: the actual one, growth term included). With no
  /// elapsed time, the ideal-gas part 2K/(dim V) alone.
  double pressure() const;
  void reset_pressure();

  /// Smallest (|r_ij| - r_i - r_j) / (r_i + r_j) over all pairs in neighbouring cells at the
  /// current time (negative: overlap); +infinity if there are no such pairs.
  double min_relative_gap() const;

  /// Cells per axis of the current cell list (1: the whole axis, all pairs along it).
  std::array<int, dim> cells_per_axis() const {
    std::array<int, dim> n;
    for (int a = 0; a < dim; ++a)
      n[a] = real_[a] ? ncross_[a] : 1;
    return n;
  }

private:
  static constexpr double kInf = std::numeric_limits<double>::infinity();
  HardSphereMD() = default; // restore_state() fills it

  /// The state of an LS growth between begin_growth() and its end (grow()'s loop variables).
  struct Growth {
    bool active = false;
    double phi_target = 0, k0 = 0, g_end = 1, rb_max = 0, d_final = 0, rb_mean = 0, v_rms = 0;
    double t_end = 0, t_window = 0;
    std::int64_t rescale_n = 1, progress_n = 1, since_rescale = 0, since_progress = 0,
                 since_window = 0;
    int stalled = 0;
  };
  void growth_rebuild();
  void growth_freeze(double g);

  /// Hot per-grain state, 64 bytes in 3D: position at local time t, velocity, base radius.
  struct alignas(dim == 3 ? 64 : 16) State {
    Vec<dim> x; ///< position at time t (consistent with the grain's cell, may be +-eps out)
    double t;   ///< local time
    Vec<dim> v;
    double rb; ///< radius at the growth origin: r(t) = rb * (1 + rate (t - t0))
  };
  /// The one calendar entry of a grain: its best collision and its next cell crossing.
  struct Slot {
    double t_coll = kInf;
    double t_cross = kInf;
    std::int32_t partner = -1;
    std::int32_t cross = 0; ///< 2 * axis + (1 if leaving through the upper face)
    std::uint64_t partner_count = 0;
  };
  struct HeapNode {
    double t;
    std::int32_t id;
  };

  // --- time stepping
  std::int64_t advance(double t_stop, std::int64_t max_collisions);
  void process_crossing(int i);
  void process_collision(int i, int j);
  void move_to_now(int i);
  void move_all_to_now();
  void set_time(double t) {
    t_now_ = t;
    g_now_ = 1.0 + rate_ * (t - t0_);
  }

  // --- predictions
  double pair_time(const Vec<dim>& xi, const Vec<dim>& vi, double rbi, int k) const;
  double crossing_time(int i, std::int32_t& cross) const;
  int gather(const std::array<int, dim>& c, int fixed_axis, int fixed_coord, int skip);
  template <bool growing>
  void best_collision(const Vec<dim>& xi, const Vec<dim>& vi, double rbi, const std::int32_t* cand,
                      int n, double& best, int& partner) const;
  void scan(int i, const std::int32_t* cand, int n, bool keep);
  void scan_full(int i);
  void scan_slab(int i, int axis, int coord);
  void predict_all();
  template <class F>
  void for_stencil(const std::array<int, dim>& c, int fixed_axis, int fixed_coord, F&& f) const;

  // --- neighbour lists (fixed radii; docs/event-driven.md)
  bool nl_possible() const;
  void nl_build();
  void nl_rebuild(int i);
  void nl_link(int i, int above);
  void nl_add(int i, int k);
  void nl_unlink(int i);
  double shell_exit_time(int i) const;

  // --- cells
  void build_cells(double d_allow);
  void cell_insert(int i, int c);
  void cell_remove(int i);
  void grow_cell_capacity();
  int flat(const std::array<int, dim>& c) const;
  void min_image(Vec<dim>& d) const;

  // --- calendar
  void heap_build();
  void heap_update(int i);
  void sift_up(std::size_t p);
  void sift_down(std::size_t p);
  double key(int i) const {
    return slots_[i].t_coll < slots_[i].t_cross ? slots_[i].t_coll : slots_[i].t_cross;
  }

  // --- bookkeeping
  void sync_output();
  void accumulate_kinetic() {
    kin_integral_ += k_track_ * (t_now_ - t_kin_);
    t_kin_ = t_now_;
  }
  void ensure_calendar();
  double min_gap_pair(int* pi, int* pj) const;

  Vec<dim> box_, half_box_;
  std::vector<State> st_;
  std::vector<double> mass_, inv_mass_;
  std::vector<std::uint64_t> count_;
  std::vector<Slot> slots_;
  std::vector<HeapNode> heap_;
  std::vector<std::int32_t> where_;

  // Cell list. Along axis a the grains cross ncross_[a] slabs of width cw_[a]. On a "real"
  // axis (>= 4 cells of side >= the largest diameter) the slabs are the cells; on the others
  // the linked lists see one cell along the axis (all pairs) and a crossing only triggers a
  // full re-prediction. The grid stays valid while the largest diameter is <= d_lim_.
  std::array<int, dim> ncross_{};
  std::array<bool, dim> real_{};
  std::array<int, dim> stride_{};
  Vec<dim> cw_;
  double d_lim_ = 0.0;
  // Members of cell c: members_[c * cap_ + m], m < count_in_[c]; cap_ doubles on overflow.
  int cap_ = 0;
  std::vector<std::int32_t> count_in_, members_, cell_of_, slot_in_cell_;
  std::vector<std::array<int, dim>> cc_; ///< slab coordinates of each grain
  std::vector<std::int32_t> cand_;       ///< scratch: grains of a stencil

  // Neighbour lists (nl_ true: fixed radii, every axis >= 4 cells of side >= d_max + 2 h).
  // Each grain stays within shell_ (h) of its centre ctr_ (its position when its list was last
  // built; a "shell exit" event rebuilds the list); its list holds every grain whose centre is
  // closer than the sum of radii + 2 h, so no other grain can touch it. The lists are symmetric.
  // The cells then hold the centres, and there are no cell crossings.
  bool nl_ = false;
  double shell_ = 0.0;
  std::vector<Vec<dim>> ctr_;
  int nb_cap_ = 0;                          ///< neighbours of i: nb_[i * nb_cap_ + m]
  std::vector<std::int32_t> nb_count_, nb_; ///< m < nb_count_[i]

  double t_now_ = 0.0;
  double t0_ = 0.0;   ///< growth origin
  double rate_ = 0.0; ///< relative growth rate (0: fixed radii)
  double g_now_ = 1.0;
  bool calendar_ok_ = false;
  std::int64_t n_collisions_ = 0;

  // pressure accumulators
  double t_press0_ = 0.0, virial_ = 0.0, kin_integral_ = 0.0, k_track_ = 0.0, t_kin_ = 0.0;

  Growth growth_;

  std::vector<Vec<dim>> out_pos_, out_vel_;
  std::vector<double> out_radii_;
};

extern template class HardSphereMD<2>;
extern template class HardSphereMD<3>;

} // namespace granpack
