#pragma once
// Geometry and kinematics of one interacting pair (docs/contact-law.md).
//
// Grain i is the first of the pair (smaller global id), j the second; r_ij points from the
// centre of i to the (nearest image of the) centre of j. The contact point is the middle of
// the overlap: branch vectors b_i = (R_i - h/2) n and b_j = -(R_j - h/2) n, so that
// x_i + b_i = x_j + b_j. With this choice a rigid motion of the pair produces no relative
// velocity at the contact (objectivity) and the pair's angular momentum is conserved exactly.
// ([AR] eq. 10 uses R_i n and -R_j n; the difference is O(h/R).)
#include <Eigen/Geometry> // cross products
#include <cmath>

#include "granpack/core/error.h"
#include "granpack/core/vec.h"

namespace granpack {

/// Velocity of a point at branch vector b from the centre of a body spinning at w: w x b.
template <int dim> inline Vec<dim> spin_velocity(const RotVec<dim>& w, const Vec<dim>& b) {
  if constexpr (dim == 3) {
    return w.cross(b);
  } else {
    return Vec<2>(-w[0] * b[1], w[0] * b[0]);
  }
}

/// Moment of force f applied at branch vector b: b x f (1 component about z in 2D).
template <int dim> inline RotVec<dim> moment(const Vec<dim>& b, const Vec<dim>& f) {
  if constexpr (dim == 3) {
    return b.cross(f);
  } else {
    RotVec<2> m;
    m[0] = b[0] * f[1] - b[1] * f[0];
    return m;
  }
}

/// Distance from a grain's centre to the contact point, the middle of the overlap: R - h/2.
/// Shared by PairGeometry, the batched kernel and the elastic moments of the engine.
inline double contact_arm(double radius, double h) {
  return radius - 0.5 * h;
}

/// Pure geometry of a pair: normal, overlap, effective radius and mass.
template <int dim> struct PairGeometry {
  Vec<dim> normal = Vec<dim>::Zero(); ///< unit vector n from i to j
  double distance = 0;                ///< |r_ij|
  double overlap = 0;                 ///< h = R_i + R_j - |r_ij| (negative: gap)
  double radius_i = 0, radius_j = 0;
  double effective_radius = 0; ///< R* = R_i R_j / (R_i + R_j)
  double effective_mass = 0;   ///< m* = m_i m_j / (m_i + m_j)

  bool touching() const { return overlap > 0; }
  /// Branch vector from the centre of i to the contact point (middle of the overlap).
  Vec<dim> branch_i() const { return contact_arm(radius_i, overlap) * normal; }
  /// Branch vector from the centre of j to the contact point.
  Vec<dim> branch_j() const { return -contact_arm(radius_j, overlap) * normal; }
};

/// Builds the pair geometry from radii, masses and the centre-to-centre vector r_ij (i -> j).
template <int dim>
inline PairGeometry<dim> make_pair_geometry(double radius_i, double radius_j, double mass_i,
                                            double mass_j, const Vec<dim>& r_ij) {
  PairGeometry<dim> g;
  g.distance = r_ij.norm();
  GRANPACK_ASSERT(g.distance > 0, "coincident grain centres");
  g.normal = r_ij / g.distance;
  g.overlap = radius_i + radius_j - g.distance;
  g.radius_i = radius_i;
  g.radius_j = radius_j;
  g.effective_radius = radius_i * radius_j / (radius_i + radius_j);
  g.effective_mass = mass_i * mass_j / (mass_i + mass_j);
  return g;
}

} // namespace granpack
