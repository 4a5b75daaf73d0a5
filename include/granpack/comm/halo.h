#pragma once
// Ghost particles: copies of grains owned by neighbouring ranks (or periodic images of our
// own) within a given width of this rank's sub-box faces, so that every pair within the
// interaction range has both grains on the rank that computes it.
//
// borders() builds the ghosts axis by axis (LAMMPS style): for axis a the candidates are all
// particles present before axis a began (owned + ghosts from earlier axes), which brings edge
// and corner ghosts without diagonal messages. Crossing the periodic boundary shifts the
// scaled coordinate by +-1, so r_ij = L (s_j - s_i) needs no minimum image afterwards.
// forward() refreshes ghost positions and velocities in the same order; reverse() adds the
// forces and torques accumulated on ghosts back into their owners. All three are collective
// on the decomposition's communicator.
//
// forward() and reverse() move their data between ranks in one of two ways (HaloTransport):
// messages (MPI_Isend/Irecv of packed buffers), or, when every rank is on one node, a
// shared-memory window (comm/shared_window.h) that each rank packs into and its neighbours
// unpack from directly, with a zero-byte message as the signal: the copy the MPI transport
// makes of each message disappears. Both copy the same doubles in the same order into the same
// places, so their results are identical bit for bit. forward_values(), reverse_values() and
// borders() always use messages.
#include <cstdint>
#include <memory>
#include <vector>

#include "granpack/comm/decomposition.h"
#include "granpack/comm/shared_window.h"
#include "granpack/core/particles.h"

namespace granpack {

/// How forward() and reverse() reach other ranks ([numerics] halo in the deck).
enum class HaloTransport {
  messages,     ///< packed buffers sent as MPI messages
  shared_memory ///< an MPI-3 shared-memory window, when every rank is on one node
};

template <int dim> class Halo {
public:
  /// shared_memory falls back to messages when the ranks span several nodes or there is only
  /// one rank.
  explicit Halo(HaloTransport transport = HaloTransport::messages) : transport_(transport) {}
  /// Clears the old ghosts and builds new ones within `width` (scaled units, per axis) of the
  /// sub-box faces. Requires width[a] <= sub-box width along a (nearest neighbours only).
  void borders(ParticleStore<dim>& p, const Decomposition<dim>& d, const Vec<dim>& width);
  /// Copies owners' position (with the image shift), velocity and angular velocity to ghosts.
  void forward(ParticleStore<dim>& p, const Decomposition<dim>& d) const;
  /// Adds ghost forces/torques into their owners (and zeroes them on the ghosts).
  void reverse(ParticleStore<dim>& p, const Decomposition<dim>& d) const;

  /// Copies a per-particle value (indexed like the store) from owners to their ghosts.
  void forward_values(std::vector<double>& values, const Decomposition<dim>& d) const;
  /// Adds ghost values into their owners (and zeroes them on the ghosts).
  void reverse_values(std::vector<double>& values, const Decomposition<dim>& d) const;

  /// Whether forward() and reverse() go through the shared-memory window (shared_memory asked
  /// for, more than one rank, all on one node; known after the first borders()).
  bool through_shared_memory() const { return window_ && window_->allocated(); }
  /// How many times borders() has (re)allocated the window (0 without one).
  int window_allocations() const { return window_ ? window_->allocations() : 0; }

private:
  struct Swap {
    int axis = 0;
    int to = 0, from = 0;          ///< ranks we send to / receive from
    double shift = 0;              ///< added to s[axis] of what we send
    std::vector<std::size_t> send; ///< local indices sent
    std::size_t recv_first = 0, recv_count = 0;
    bool self = false; ///< to == from == this rank: the ghosts are our own images
  };
  /// forward()/reverse() of a self swap, in place instead of through message buffers.
  void copy_to_images(ParticleStore<dim>& p, const Swap& sw) const;
  void add_from_images(ParticleStore<dim>& p, const Swap& sw) const;
  /// The shared-memory window for d's communicator (created at the first borders(), and again
  /// if d's ranks change), with room for every slot of the current ghost lists. Collective.
  void prepare_window(const Decomposition<dim>& d);
  /// Where swap q of an axis's exchange packs its n doubles: this rank's window slot (shared)
  /// or the message buffer out_[q].
  double* outgoing(bool shared, int kind, int axis, int q, int parity, std::size_t n) const;
  /// Delivers what an axis's two swaps packed (to ranks to[q]) and points in[q] at what ranks
  /// from[q] packed for us (n_in[q] doubles): the writer's window slot after the notifications
  /// (shared), or in_[q] after the messages. Collective with the axis's neighbours.
  void deliver(bool shared, int kind, int axis, int parity, const Decomposition<dim>& d,
               const std::size_t (&n_in)[2], const int (&to)[2], const int (&from)[2],
               const double* (&in)[2]) const;
  /// The window's slot for (kind: 0 forward, 1 reverse; axis; q: the swap towards -1 or +1;
  /// parity of the exchange), the same on every rank (halo.cpp explains the double buffer).
  static std::size_t slot(int kind, int axis, int q, int parity) {
    return static_cast<std::size_t>(((kind * dim + axis) * 2 + q) * 2 + parity);
  }

  HaloTransport transport_ = HaloTransport::messages;
  std::vector<Swap> swaps_;
  // Message buffers kept between steps: no allocation (and no page faults of fresh large
  // blocks) in forward()/reverse(), which run every step.
  // Two of each: the two exchanges of an axis run at once.
  mutable std::vector<double> out_[2], in_[2];
  /// The shared-memory path (transport_ == shared_memory and more than one rank); a
  /// unique_ptr so that a Halo stays movable. Destroying it is collective (every rank destroys
  /// its Halo), and it must happen before MPI_Finalize: every Halo lives inside main's MPI scope.
  std::unique_ptr<SharedWindow> window_;
  /// Exchanges done through the window (the same count on every rank: forward() and reverse()
  /// are collective); their parity picks the slots of the double buffer (halo.cpp).
  mutable std::uint64_t forward_exchanges_ = 0, reverse_exchanges_ = 0;
};

extern template class Halo<2>;
extern template class Halo<3>;

} // namespace granpack
