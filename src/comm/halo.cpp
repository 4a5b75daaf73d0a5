#include "granpack/comm/halo.h"

#include <mpi.h>

#include <algorithm>
#include <sstream>

#include "granpack/comm/particle_packing.h"
#include "granpack/core/error.h"

namespace granpack {

namespace {
/// Exchanges variable-length double buffers with two (possibly equal, possibly self) ranks.
std::vector<double> sendrecv(MPI_Comm comm, const std::vector<double>& out, int to, int from) {
  long long n_out = static_cast<long long>(out.size()), n_in = 0;
  MPI_Sendrecv(&n_out, 1, MPI_LONG_LONG, to, 11, &n_in, 1, MPI_LONG_LONG, from, 11, comm,
               MPI_STATUS_IGNORE);
  std::vector<double> in(static_cast<std::size_t>(n_in));
  MPI_Sendrecv(out.data(), static_cast<int>(n_out), MPI_DOUBLE, to, 12, in.data(),
               static_cast<int>(n_in), MPI_DOUBLE, from, 12, comm, MPI_STATUS_IGNORE);
  return in;
}

/// The two exchanges of one axis (towards -1 and +1) with other ranks, whose lengths the
/// receivers know (forward/reverse: the ghost lists are fixed between rebuilds). They are
/// independent (both read what existed before the axis began), so they run at once: both
/// receives and sends posted, one wait, one latency instead of two. (An axis along which this
/// rank is alone never comes here: its ghosts are its own images, copied in place.)
void exchange_axis(MPI_Comm comm, std::vector<double> (&out)[2], std::vector<double> (&in)[2],
                   const std::size_t (&n_in)[2], const int (&to)[2], const int (&from)[2],
                   int tag) {
  MPI_Request req[4];
  for (int q = 0; q < 2; ++q) {
    in[q].resize(n_in[q]);
    MPI_Irecv(in[q].data(), static_cast<int>(n_in[q]), MPI_DOUBLE, from[q], tag + q, comm, &req[q]);
  }
  for (int q = 0; q < 2; ++q)
    MPI_Isend(out[q].data(), static_cast<int>(out[q].size()), MPI_DOUBLE, to[q], tag + q, comm,
              &req[2 + q]);
  MPI_Waitall(4, req, MPI_STATUSES_IGNORE);
}
} // namespace

template <int dim>
void Halo<dim>::borders(ParticleStore<dim>& p, const Decomposition<dim>& d, const Vec<dim>& width) {
  p.clear_ghosts();
  swaps_.clear();
  int me = 0;
  MPI_Comm_rank(d.comm(), &me);
  for (int a = 0; a < dim; ++a) {
    // The narrowest slab of the axis, the same on every rank (the cuts and the width are
    // global), so every rank throws together. Ghosts come from the nearest sub-domain only: a
    // narrower one would lose pairs.
    const double box = d.narrowest(a);
    if (width[a] > box) {
      std::ostringstream os;
      os << d.dims()[a] << " ranks along axis " << a << " cut the cell into sub-domains of "
         << (d.uniform() ? "" : "(the narrowest) ") << box
         << " of its length, narrower than the interaction range of the grains (ghost "
         << "layer: " << width[a] << " of the cell length): run on fewer ranks (at most "
         << static_cast<int>(1.0 / width[a]) << " along this axis) or on a larger sample";
      throw InputError(os.str());
    }
    const std::size_t candidates = p.size(); // owned + ghosts of earlier axes
    for (int dir : {-1, +1}) {
      Swap sw;
      sw.axis = a;
      MPI_Cart_shift(d.comm(), a, dir, &sw.from, &sw.to);
      sw.self = sw.from == me && sw.to == me;
      // Leaving through the periodic boundary: lower face of coord 0 or upper of the last.
      if (dir < 0 && d.coords()[a] == 0)
        sw.shift = 1.0;
      if (dir > 0 && d.coords()[a] == d.dims()[a] - 1)
        sw.shift = -1.0;
      std::vector<double> buf;
      for (std::size_t i = 0; i < candidates; ++i) {
        double s = p.position[i][a];
        bool near = dir < 0 ? s < d.lo()[a] + width[a] : s >= d.hi()[a] - width[a];
        if (!near)
          continue;
        sw.send.push_back(i);
        std::size_t at = buf.size();
        Packing<dim>::pack_particle(p, i, buf);
        buf[at + 4 + a] += sw.shift; // position[a] sits after id, radius, mass, inertia
      }
      std::vector<double> in = sendrecv(d.comm(), buf, sw.to, sw.from);
      sw.recv_first = p.size();
      std::size_t pos = 0;
      while (pos < in.size())
        p.add_ghost(Packing<dim>::unpack_particle(in.data(), pos));
      sw.recv_count = p.size() - sw.recv_first;
      swaps_.push_back(std::move(sw));
    }
  }
  prepare_window(d);
}

// The shared-memory path (HaloTransport::shared_memory)
// ------------------------------------------------------
// Each rank's segment of the window holds one slot per (direction kind, axis, q, parity):
// kind forward or reverse, q the swap of the axis (towards -1 or +1), parity that of the
// kind's exchange count. A writer packs what it would send to rank to[q] into its own slot,
// exactly as into out_[q]; the reader unpacks from the writer's slot, exactly as from in_[q],
// after the notification of that exchange (SharedWindow::notify: zero-byte messages with
// MPI_Win_sync around them). Same doubles, same order, same places, same sums: the results
// are those of the message path bit for bit.
//
// Why the double buffer is safe (no rank overwrites a slot before its reader is done with it):
// count a kind's exchanges n = 0, 1, 2, ... (forward and reverse separately); every rank has
// the same count, since forward() and reverse() are collective. In exchange n of an axis, rank
// R writes its slots of parity n % 2 for its two neighbours along the axis (to[0] below, to[1]
// above in forward; the other way round in reverse), which read them during their exchange n.
// R writes those slots again only in exchange n + 2. Before that, R has completed exchange
// n + 1, whose wait receives the notification of exchange n + 1 from each of its two
// neighbours: the ranks R hears from (from[0], from[1]) are the ranks it writes for (to[1],
// to[0]). A rank sends its notifications of exchange n + 1 only after it has unpacked all of
// exchange n (program order; the MPI_Win_sync before the sends orders those loads before
// them). So every read of exchange n is over before any write of exchange n + 2 begins. The
// writes of exchange n + 1 go to the other parity, whose reads (exchange n - 1) ended before R
// completed exchange n, by the same argument. With 2 ranks along the axis both neighbours are
// one rank T (to[0] = to[1] = from[0] = from[1] = T): R writes both slots for T and waits for
// both of T's notifications (tags tag + 0 and tag + 1, each matched by its own receive), which
// T sends only after unpacking both of R's slots of the exchange before; the argument holds
// unchanged. Successive notifications between the same pair with the same tag are matched in
// the order sent (MPI's non-overtaking rule). Forward and reverse have their own slots and
// counts and each axis its own slots, so their interleaving does not matter; an axis with one
// rank never uses the window (its ghosts are our own images, copied in place).
// The window is reallocated only in borders(), collectively, after every rank finished its
// last exchange (SharedWindow::release synchronises before it frees).
namespace {
constexpr int kForward = 0, kReverse = 1;
}

template <int dim> void Halo<dim>::prepare_window(const Decomposition<dim>& d) {
  if (transport_ != HaloTransport::shared_memory || d.size() == 1) {
    window_.reset();
    return;
  }
  if (!window_ || !window_->serves(d.comm())) {
    window_.reset(); // frees the old window first (collective on its ranks: the same ranks)
    window_ = std::make_unique<SharedWindow>(d.comm());
  }
  if (!window_->on_one_node())
    return; // messages (run_deck logs it once)
  constexpr std::size_t per_forward = 2 * dim + rot_dim<dim>, per_reverse = dim + rot_dim<dim>;
  std::vector<std::size_t> need(2 * dim * 2 * 2, 0);
  for (std::size_t s = 0; s < swaps_.size(); ++s) {
    const Swap& sw = swaps_[s];
    if (sw.self)
      continue;
    const int q = static_cast<int>(s % 2);
    for (int parity = 0; parity < 2; ++parity) {
      need[slot(kForward, sw.axis, q, parity)] = sw.send.size() * per_forward;
      need[slot(kReverse, sw.axis, q, parity)] = sw.recv_count * per_reverse;
    }
  }
  window_->reserve(need);
}

template <int dim>
double* Halo<dim>::outgoing(bool shared, int kind, int axis, int q, int parity,
                            std::size_t n) const {
  if (shared)
    return window_->mine(slot(kind, axis, q, parity));
  out_[q].resize(n);
  return out_[q].data();
}

template <int dim>
void Halo<dim>::deliver(bool shared, int kind, int axis, int parity, const Decomposition<dim>& d,
                        const std::size_t (&n_in)[2], const int (&to)[2], const int (&from)[2],
                        const double* (&in)[2]) const {
  const int tag = kind == kForward ? 30 : 40;
  if (shared) {
    window_->notify(to, from, tag);
    for (int q = 0; q < 2; ++q)
      in[q] = window_->of(from[q], slot(kind, axis, q, parity));
  } else {
    exchange_axis(d.comm(), out_, in_, n_in, to, from, tag);
    for (int q = 0; q < 2; ++q)
      in[q] = in_[q].data();
  }
}

template <int dim>
void Halo<dim>::forward(ParticleStore<dim>& p, const Decomposition<dim>& d) const {
  constexpr int per = 2 * dim + rot_dim<dim>;
  const bool shared = through_shared_memory();
  const int parity = static_cast<int>(forward_exchanges_ % 2);
  if (shared)
    ++forward_exchanges_;
  // swaps_ holds, per axis, the exchange towards -1 then the one towards +1 (borders()).
  for (std::size_t s0 = 0; s0 < swaps_.size(); s0 += 2) {
    if (swaps_[s0].self) { // then both are: one rank along the axis
      // One rank along the axis: the ghosts are images of our own grains, copied in place
      // (no buffer: half the memory traffic of pack + unpack).
      for (int q = 0; q < 2; ++q)
        copy_to_images(p, swaps_[s0 + q]);
      continue;
    }
    const int axis = swaps_[s0].axis;
    std::size_t n_in[2];
    int to[2], from[2];
    const double* in[2];
    for (int q = 0; q < 2; ++q) {
      const Swap& sw = swaps_[s0 + q];
      double* o = outgoing(shared, kForward, axis, q, parity, sw.send.size() * per);
      for (std::size_t i : sw.send) {
        for (int a = 0; a < dim; ++a)
          *o++ = p.position[i][a] + (a == sw.axis ? sw.shift : 0.0);
        for (int a = 0; a < dim; ++a)
          *o++ = p.velocity[i][a];
        for (int a = 0; a < rot_dim<dim>; ++a)
          *o++ = p.angular_velocity[i][a];
      }
      n_in[q] = sw.recv_count * per;
      to[q] = sw.to;
      from[q] = sw.from;
    }
    deliver(shared, kForward, axis, parity, d, n_in, to, from, in);
    for (int q = 0; q < 2; ++q) {
      const Swap& sw = swaps_[s0 + q];
      const double* i = in[q];
      for (std::size_t g = sw.recv_first; g < sw.recv_first + sw.recv_count; ++g) {
        for (int a = 0; a < dim; ++a)
          p.position[g][a] = *i++;
        for (int a = 0; a < dim; ++a)
          p.velocity[g][a] = *i++;
        for (int a = 0; a < rot_dim<dim>; ++a)
          p.angular_velocity[g][a] = *i++;
      }
    }
  }
}

template <int dim>
void Halo<dim>::reverse(ParticleStore<dim>& p, const Decomposition<dim>& d) const {
  constexpr int per = dim + rot_dim<dim>;
  const bool shared = through_shared_memory();
  const int parity = static_cast<int>(reverse_exchanges_ % 2);
  if (shared)
    ++reverse_exchanges_;
  // Axes in reverse order (ghosts of later axes may be images of earlier axes' ghosts).
  for (std::size_t s0 = swaps_.size(); s0 >= 2; s0 -= 2) {
    if (swaps_[s0 - 2].self) {
      // +1 then -1, as below. The owners an axis adds into existed before the axis began and
      // its ghosts came after, so adding one swap's ghosts before zeroing the other's changes
      // nothing: the same sums in the same order as through buffers.
      for (int q = 1; q >= 0; --q)
        add_from_images(p, swaps_[s0 - 2 + q]);
      continue;
    }
    const int axis = swaps_[s0 - 2].axis;
    std::size_t n_in[2];
    int to[2], from[2];
    const double* in[2];
    for (int q = 0; q < 2; ++q) {
      const Swap& sw = swaps_[s0 - 2 + q];
      double* o = outgoing(shared, kReverse, axis, q, parity, sw.recv_count * per);
      for (std::size_t g = sw.recv_first; g < sw.recv_first + sw.recv_count; ++g) {
        for (int a = 0; a < dim; ++a)
          *o++ = p.force[g][a];
        for (int a = 0; a < rot_dim<dim>; ++a)
          *o++ = p.torque[g][a];
        p.force[g].setZero();
        p.torque[g].setZero();
      }
      // Back along the way they came: to the rank we received from.
      n_in[q] = sw.send.size() * per;
      to[q] = sw.from;
      from[q] = sw.to;
    }
    deliver(shared, kReverse, axis, parity, d, n_in, to, from, in);
    for (int q = 1; q >= 0; --q) { // +1 then -1, the order of the swaps reversed
      const Swap& sw = swaps_[s0 - 2 + q];
      const double* i = in[q];
      for (std::size_t k : sw.send) {
        for (int a = 0; a < dim; ++a)
          p.force[k][a] += *i++;
        for (int a = 0; a < rot_dim<dim>; ++a)
          p.torque[k][a] += *i++;
      }
    }
  }
}

template <int dim> void Halo<dim>::copy_to_images(ParticleStore<dim>& p, const Swap& sw) const {
  std::size_t g = sw.recv_first;
  for (std::size_t i : sw.send) {
    p.position[g] = p.position[i];
    p.position[g][sw.axis] += sw.shift;
    p.velocity[g] = p.velocity[i];
    p.angular_velocity[g] = p.angular_velocity[i];
    ++g;
  }
}

template <int dim> void Halo<dim>::add_from_images(ParticleStore<dim>& p, const Swap& sw) const {
  std::size_t g = sw.recv_first;
  for (std::size_t i : sw.send) {
    p.force[i] += p.force[g];
    p.torque[i] += p.torque[g];
    p.force[g].setZero();
    p.torque[g].setZero();
    ++g;
  }
}

template <int dim>
void Halo<dim>::forward_values(std::vector<double>& values, const Decomposition<dim>& d) const {
  std::vector<double> buf;
  for (const Swap& sw : swaps_) {
    buf.clear();
    for (std::size_t i : sw.send)
      buf.push_back(values[i]);
    std::vector<double> in = sendrecv(d.comm(), buf, sw.to, sw.from);
    GRANPACK_CHECK(in.size() == sw.recv_count, "halo forward_values: ghost count changed");
    std::copy(in.begin(), in.end(), values.begin() + static_cast<std::ptrdiff_t>(sw.recv_first));
  }
}

template <int dim>
void Halo<dim>::reverse_values(std::vector<double>& values, const Decomposition<dim>& d) const {
  std::vector<double> buf;
  for (auto it = swaps_.rbegin(); it != swaps_.rend(); ++it) {
    const Swap& sw = *it;
    buf.assign(values.begin() + static_cast<std::ptrdiff_t>(sw.recv_first),
               values.begin() + static_cast<std::ptrdiff_t>(sw.recv_first + sw.recv_count));
    std::fill_n(values.begin() + static_cast<std::ptrdiff_t>(sw.recv_first), sw.recv_count, 0.0);
    std::vector<double> in = sendrecv(d.comm(), buf, sw.from, sw.to);
    GRANPACK_CHECK(in.size() == sw.send.size(), "halo reverse_values: ghost count changed");
    for (std::size_t k = 0; k < sw.send.size(); ++k)
      values[sw.send[k]] += in[k];
  }
}

template class Halo<2>;
template class Halo<3>;

} // namespace granpack
