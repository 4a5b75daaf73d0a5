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
#include <vector>

#include "granpack/comm/decomposition.h"
#include "granpack/core/particles.h"

namespace granpack {

template <int dim> class Halo {
public:
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

  std::vector<Swap> swaps_;
  // Message buffers kept between steps: no allocation (and no page faults of fresh large
  // blocks) in forward()/reverse(), which run every step.
  // Two of each: the two exchanges of an axis run at once.
  mutable std::vector<double> out_[2], in_[2];
};

extern template class Halo<2>;
extern template class Halo<3>;

} // namespace granpack
