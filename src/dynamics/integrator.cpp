#include "granpack/dynamics/integrator.h"

#include <Eigen/Geometry>
#include <cmath>

namespace granpack {

template <int dim> void kick(ParticleStore<dim>& p, double h) {
  // Flat arrays through raw pointers (x, y[, z] per grain): the compiler can then keep them
  // in registers and vectorise; the arithmetic is the same as v += (h/m) F, ω += (h/I) M.
  constexpr int rd = rot_dim<dim>;
  static_assert(sizeof(Vec<dim>) == dim * sizeof(double) && sizeof(RotVec<dim>) == rd * sizeof(double));
  const std::size_t n = p.n_owned();
  double* v = p.velocity.data()->data();
  double* w = p.angular_velocity.data()->data();
  const double* f = p.force.data()->data();
  const double* t = p.torque.data()->data();
  const double* m = p.mass.data();
  const double* inertia = p.inertia.data();
  for (std::size_t i = 0; i < n; ++i) {
    const double a = h / m[i], b = h / inertia[i];
    for (int k = 0; k < dim; ++k) v[dim * i + k] += a * f[dim * i + k];
    for (int k = 0; k < rd; ++k) w[rd * i + k] += b * t[rd * i + k];
  }
}

template <int dim> void drift(ParticleStore<dim>& p, const Cell<dim>& cell, double dt) {
  const std::size_t n = p.n_owned();
  const Vec<dim> inv_l = cell.length.cwiseInverse();
  double* s = p.position.data()->data();
  const double* v = p.velocity.data()->data();
  for (std::size_t i = 0; i < n; ++i)
    for (int k = 0; k < dim; ++k) s[dim * i + k] += dt * (v[dim * i + k] * inv_l[k]);
  if constexpr (dim == 3) {
    // q <- exp(dt omega / 2) q, renormalised: orientation is output only.
    // dq = (cos y, sin(y)/y u) with u = ω dt/2, y = |u|. For y < 1e-3 (always, in MD:
    // y ~ 1e-7) the Taylor series to y⁴ is exact to rounding and spares the square root,
    // sin and cos per grain and step.
    const double* w = p.angular_velocity.data()->data();
    double* o = p.orientation.data()->data();
    static_assert(sizeof(OrientVec<3>) == 4 * sizeof(double));
    for (std::size_t i = 0; i < n; ++i) {
      const double ux = 0.5 * dt * w[3 * i], uy = 0.5 * dt * w[3 * i + 1], uz = 0.5 * dt * w[3 * i + 2];
      const double y2 = ux * ux + uy * uy + uz * uz;
      if (!(y2 > 0)) continue;
      double cw, sv;  // cos y, sin(y)/y
      if (y2 < 1e-6) {
        cw = 1.0 - y2 * (1.0 / 2.0 - y2 * (1.0 / 24.0));
        sv = 1.0 - y2 * (1.0 / 6.0 - y2 * (1.0 / 120.0));
      } else {
        const double y = std::sqrt(y2);
        cw = std::cos(y);
        sv = std::sin(y) / y;
      }
      const double dx = sv * ux, dy = sv * uy, dz = sv * uz;
      double* q = o + 4 * i;  // (w, x, y, z)
      const double qw = q[0], qx = q[1], qy = q[2], qz = q[3];
      // Hamilton product dq * q
      const double rw = cw * qw - (dx * qx + dy * qy + dz * qz);
      const double rx = cw * qx + qw * dx + (dy * qz - dz * qy);
      const double ry = cw * qy + qw * dy + (dz * qx - dx * qz);
      const double rz = cw * qz + qw * dz + (dx * qy - dy * qx);
      const double inv = 1.0 / std::sqrt(rw * rw + rx * rx + ry * ry + rz * rz);
      q[0] = rw * inv;
      q[1] = rx * inv;
      q[2] = ry * inv;
      q[3] = rz * inv;
    }
  } else {
    for (std::size_t i = 0; i < n; ++i) p.orientation[i][0] += dt * p.angular_velocity[i][0];
  }
}

template <int dim> Vec<dim> momentum(const ParticleStore<dim>& p) {
  Vec<dim> m = Vec<dim>::Zero();
  for (std::size_t i = 0; i < p.n_owned(); ++i) m += p.mass[i] * p.velocity[i];
  return m;
}

template <int dim> double kinetic_energy(const ParticleStore<dim>& p) {
  double e = 0;
  for (std::size_t i = 0; i < p.n_owned(); ++i)
    e += 0.5 * p.mass[i] * p.velocity[i].squaredNorm() +
         0.5 * p.inertia[i] * p.angular_velocity[i].squaredNorm();
  return e;
}

template void kick<2>(ParticleStore<2>&, double);
template void kick<3>(ParticleStore<3>&, double);
template void drift<2>(ParticleStore<2>&, const Cell<2>&, double);
template void drift<3>(ParticleStore<3>&, const Cell<3>&, double);
template Vec<2> momentum<2>(const ParticleStore<2>&);
template Vec<3> momentum<3>(const ParticleStore<3>&);
template double kinetic_energy<2>(const ParticleStore<2>&);
template double kinetic_energy<3>(const ParticleStore<3>&);

}  // namespace granpack
