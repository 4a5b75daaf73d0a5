#include "granpack/core/particles.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <numeric>

namespace granpack {

template <> double HomogeneousGrain<3>::mass(double rho, double d) {
  return rho * std::numbers::pi * d * d * d / 6.0;
}
template <> double HomogeneousGrain<3>::inertia(double m, double d) {
  return m * d * d / 10.0;
}
template <> double HomogeneousGrain<2>::mass(double rho, double d) {
  return rho * std::numbers::pi * d * d / 4.0;
}
template <> double HomogeneousGrain<2>::inertia(double m, double d) {
  return m * d * d / 8.0;
}

template <int dim> void ParticleStore<dim>::reserve(std::size_t n) {
  id.reserve(n);
  radius.reserve(n);
  mass.reserve(n);
  inertia.reserve(n);
  position.reserve(n);
  velocity.reserve(n);
  force.reserve(n);
  angular_velocity.reserve(n);
  torque.reserve(n);
  orientation.reserve(n);
}

template <int dim> void ParticleStore<dim>::resize(std::size_t n) {
  id.resize(n);
  radius.resize(n);
  mass.resize(n);
  inertia.resize(n);
  position.resize(n);
  velocity.resize(n);
  force.resize(n, Vec<dim>::Zero());
  angular_velocity.resize(n);
  torque.resize(n, RotVec<dim>::Zero());
  orientation.resize(n);
}

template <int dim> void ParticleStore<dim>::push(const Particle<dim>& p) {
  id.push_back(p.id);
  radius.push_back(p.radius);
  mass.push_back(p.mass);
  inertia.push_back(p.inertia);
  position.push_back(p.position);
  velocity.push_back(p.velocity);
  force.push_back(Vec<dim>::Zero());
  angular_velocity.push_back(p.angular_velocity);
  torque.push_back(RotVec<dim>::Zero());
  orientation.push_back(p.orientation);
}

template <int dim> void ParticleStore<dim>::add_owned(const Particle<dim>& p) {
  assert(n_ghost() == 0 && "clear ghosts before adding owned particles");
  push(p);
  ++n_owned_;
}

template <int dim> void ParticleStore<dim>::add_ghost(const Particle<dim>& p) {
  push(p);
}

template <int dim> Particle<dim> ParticleStore<dim>::get(std::size_t i) const {
  Particle<dim> p;
  p.id = id[i];
  p.radius = radius[i];
  p.mass = mass[i];
  p.inertia = inertia[i];
  p.position = position[i];
  p.velocity = velocity[i];
  p.angular_velocity = angular_velocity[i];
  p.orientation = orientation[i];
  return p;
}

template <int dim> void ParticleStore<dim>::set(std::size_t i, const Particle<dim>& p) {
  id[i] = p.id;
  radius[i] = p.radius;
  mass[i] = p.mass;
  inertia[i] = p.inertia;
  position[i] = p.position;
  velocity[i] = p.velocity;
  angular_velocity[i] = p.angular_velocity;
  orientation[i] = p.orientation;
}

template <int dim> void ParticleStore<dim>::remove_owned(std::vector<std::size_t> indices) {
  assert(n_ghost() == 0 && "clear ghosts before removing owned particles");
  // Highest index first, so that the particle swapped in from the end is never one of the
  // indices still to be removed.
  std::sort(indices.begin(), indices.end(), std::greater<>());
  for (std::size_t i : indices) {
    std::size_t last = n_owned_ - 1;
    if (i != last) {
      set(i, get(last));
      force[i] = force[last];
      torque[i] = torque[last];
    }
    --n_owned_;
    resize(n_owned_);
  }
}

template <int dim>
void ParticleStore<dim>::sort_owned_spatially(const std::array<std::size_t, dim>& bins) {
  assert(n_ghost() == 0 && "clear ghosts before sorting");
  std::vector<std::uint64_t> key(n_owned_);
  for (std::size_t i = 0; i < n_owned_; ++i) {
    std::uint64_t k = 0;
    for (int a = 0; a < dim; ++a) {
      // Owned scaled positions are in [0, 1); the clamp only guards round-off at 1.
      const double s = position[i][a] - std::floor(position[i][a]);
      const auto b =
          std::min(bins[a] - 1, static_cast<std::size_t>(s * static_cast<double>(bins[a])));
      k = k * bins[a] + b;
    }
    key[i] = k;
  }
  std::vector<std::size_t> order(n_owned_);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return key[a] != key[b] ? key[a] < key[b] : id[a] < id[b];
  });
  auto permute = [&](auto& v) {
    std::remove_reference_t<decltype(v)> out;
    out.reserve(v.size());
    for (std::size_t k : order)
      out.push_back(v[k]);
    v.swap(out);
  };
  permute(id);
  permute(radius);
  permute(mass);
  permute(inertia);
  permute(position);
  permute(velocity);
  permute(force);
  permute(angular_velocity);
  permute(torque);
  permute(orientation);
}

template <int dim> void ParticleStore<dim>::clear_forces() {
  std::fill(force.begin(), force.end(), Vec<dim>::Zero());
  std::fill(torque.begin(), torque.end(), RotVec<dim>::Zero());
}

template class ParticleStore<2>;
template class ParticleStore<3>;

} // namespace granpack
