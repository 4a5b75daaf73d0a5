#pragma once
// The periodic orthorhombic cell: lengths L_alpha and their rates dL_alpha/dt.
// Positions are stored scaled, s in [0,1)^dim, and r = L.s ([AR] sec. II B), so a change of
// the cell lengths moves every grain affinely without touching the particle arrays.
#include <cmath>

#include "granpack/core/vec.h"

namespace granpack {

template <int dim> struct Cell {
  Vec<dim> length = Vec<dim>::Ones(); ///< L_alpha (m)
  Vec<dim> rate = Vec<dim>::Zero();   ///< dL_alpha/dt (m/s)

  /// Volume (3D) or area (2D) of the cell, Omega = prod L_alpha.
  double volume() const { return length.prod(); }
  Vec<dim> to_real(const Vec<dim>& s) const { return length.cwiseProduct(s); }
  Vec<dim> to_scaled(const Vec<dim>& r) const { return r.cwiseQuotient(length); }

  /// Folds a scaled position back into [0,1)^dim.
  static Vec<dim> wrap(Vec<dim> s) {
    for (int a = 0; a < dim; ++a) {
      s[a] -= std::floor(s[a]);
      if (s[a] >= 1.0)
        s[a] = 0.0; // -tiny - floor(-tiny) rounds to exactly 1.0
    }
    return s;
  }

  /// Real vector from grain i to the nearest periodic image of grain j, given scaled
  /// positions: r_ij of [AR] eq. (7)-(10).
  Vec<dim> min_image(const Vec<dim>& si, const Vec<dim>& sj) const {
    Vec<dim> ds = sj - si;
    for (int a = 0; a < dim; ++a)
      ds[a] -= std::nearbyint(ds[a]);
    return length.cwiseProduct(ds);
  }
};

} // namespace granpack
