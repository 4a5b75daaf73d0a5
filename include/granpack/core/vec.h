#pragma once
// Small fixed-size vector types shared by every layer, templated on the space dimension.
#include <Eigen/Core>
#include <cstdint>

namespace granpack {

/// Position, velocity, force: dim components.
template <int dim> using Vec = Eigen::Matrix<double, dim, 1>;

/// Second-order tensors (stress, virial): dim x dim.
template <int dim> using Tensor = Eigen::Matrix<double, dim, dim>;

/// Number of rotational degrees of freedom: 1 in 2D (about z), 3 in 3D.
template <int dim> inline constexpr int rot_dim = dim*(dim - 1) / 2;

/// Angular velocity, torque, rotation increments: rot_dim<dim> components.
template <int dim> using RotVec = Eigen::Matrix<double, rot_dim<dim>, 1>;

/// Orientation kept for output: a unit quaternion (w, x, y, z) in 3D, an angle in 2D.
template <int dim> inline constexpr int orient_dim = dim == 3 ? 4 : 1;
template <int dim> using OrientVec = Eigen::Matrix<double, orient_dim<dim>, 1>;

/// The identity orientation.
template <int dim> OrientVec<dim> identity_orientation() {
  OrientVec<dim> q = OrientVec<dim>::Zero();
  if constexpr (dim == 3)
    q[0] = 1.0;
  return q;
}

/// Global particle identifier: unique over the whole sample, stable for its lifetime.
using GlobalId = std::int64_t;

} // namespace granpack
