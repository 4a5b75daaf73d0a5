#pragma once
// Particle store: structure of arrays, owned particles first, ghosts after them.
//
// Conventions (documented in docs/ARCHITECTURE.md):
//  - position is SCALED, s in [0,1)^dim for owned grains; r = L.s (Cell::to_real). Ghost
//    copies of periodic images carry s shifted by +-1 so that r_j - r_i is direct.
//  - velocity is the fluctuating velocity L.ds/dt in m/s (the affine part dL/dt.s is not
//    included): it is what enters the kinetic stress of [AR] eq. (7)-(8).
//  - angular_velocity/torque have rot_dim<dim> components (1 in 2D, 3 in 3D).
#include <array>
#include <cassert>
#include <cstddef>
#include <vector>

#include "granpack/core/vec.h"

namespace granpack {

/// One particle as a value, for building samples, migration and I/O.
template <int dim> struct Particle {
  GlobalId id = -1;
  double radius = 0, mass = 0, inertia = 0;
  Vec<dim> position = Vec<dim>::Zero();
  Vec<dim> velocity = Vec<dim>::Zero();
  RotVec<dim> angular_velocity = RotVec<dim>::Zero();
  OrientVec<dim> orientation = identity_orientation<dim>();
};

/// Volume, mass and moment of inertia of a homogeneous sphere (3D) or disk of unit thickness
/// (2D) of density rho and diameter d: m = rho V with V = pi d^3/6 and I = m d^2/10 in 3D,
/// V = pi d^2/4 and I = m d^2/8 in 2D.
template <int dim> struct HomogeneousGrain {
  static double mass(double rho, double d);
  /// Volume (area in 2D): the mass at unit density (rounds exactly as pi d^3/6, pi d^2/4).
  static double volume(double d) { return mass(1.0, d); }
  static double inertia(double m, double d);
};

template <int dim> class ParticleStore {
public:
  std::vector<GlobalId> id;
  std::vector<double> radius, mass, inertia;
  std::vector<Vec<dim>> position, velocity, force;
  std::vector<RotVec<dim>> angular_velocity, torque;
  std::vector<OrientVec<dim>> orientation;

  std::size_t size() const { return id.size(); }
  std::size_t n_owned() const { return n_owned_; }
  std::size_t n_ghost() const { return size() - n_owned_; }

  void reserve(std::size_t n);
  /// Appends an owned particle. Ghosts must have been cleared first (owned come first).
  void add_owned(const Particle<dim>& p);
  /// Appends a ghost copy; `p.position` is already shifted to the image the owner sees.
  void add_ghost(const Particle<dim>& p);
  void clear_ghosts() { resize(n_owned_); }
  /// Removes the owned particles at the given indices (any order); ghosts must be cleared.
  /// Order of the remaining particles is not preserved (swap with last).
  void remove_owned(std::vector<std::size_t> indices);
  /// Puts the owned particles (ghosts must be cleared) in a canonical order that keeps
  /// neighbours close in memory: by the bin, on a grid of bins[a] slices per axis (row-major,
  /// the last axis fastest), of their scaled position, then by id. It is a function of the
  /// positions and ids alone, so a restarted run that reads them from a checkpoint sums
  /// forces in the same order as the interrupted run; all-ones bins give plain id order.
  void sort_owned_spatially(const std::array<std::size_t, dim>& bins);
  Particle<dim> get(std::size_t i) const;
  void set(std::size_t i, const Particle<dim>& p);
  /// Zeroes force and torque of every particle (owned and ghost).
  void clear_forces();

private:
  void resize(std::size_t n);
  void push(const Particle<dim>& p);
  std::size_t n_owned_ = 0;
};

extern template class ParticleStore<2>;
extern template class ParticleStore<3>;

} // namespace granpack
