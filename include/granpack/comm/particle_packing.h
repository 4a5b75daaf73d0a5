#pragma once
// Packing particles and contacts into flat double buffers for MPI messages. Global ids and
// flags travel as doubles: exact for ids below 2^53, far beyond any sample.
#include <cstddef>
#include <vector>

#include "granpack/core/contact_store.h"
#include "granpack/core/particles.h"

namespace granpack {

template <int dim> struct Packing {
  /// doubles per particle: id, radius, mass, inertia, position, velocity, omega, orientation
  static constexpr int particle_size = 4 + 2 * dim + rot_dim<dim> + orient_dim<dim>;
  /// doubles per contact: first, second, normal_force, tangential_force, rolling, flags, age
  static constexpr int contact_size = 5 + dim + rot_dim<dim>;

  static void pack_particle(const ParticleStore<dim>& p, std::size_t i, std::vector<double>& buf);
  /// Reads one particle at buf[pos], advances pos.
  static Particle<dim> unpack_particle(const double* buf, std::size_t& pos);
  static void pack_contact(const ContactKey& k, const ContactState<dim>& s,
                           std::vector<double>& buf);
  static void unpack_contact(const double* buf, std::size_t& pos, ContactKey& k,
                             ContactState<dim>& s);
};

extern template struct Packing<2>;
extern template struct Packing<3>;

} // namespace granpack
