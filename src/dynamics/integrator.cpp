#include "granpack/dynamics/integrator.h"

#include <algorithm>
#include <cmath>

#include "granpack/contact/tangential.h" // small_angle_series, kSmallAngleSquared
#include "granpack/core/simd_clones.h"

namespace granpack {

namespace {
/// x[d i + k] += (h / m[i]) y[d i + k] for grains i < n, components k < d.
GRANPACK_SIMD_CLONES
void kick_flat(double* x, const double* y, const double* m, std::size_t n, int d, double h) {
  // One loop per component count, each with a fixed inner length the compiler unrolls.
  auto run = [&]<int c>() {
    for (std::size_t i = 0; i < n; ++i) {
      const double a = h / m[i];
      for (int k = 0; k < c; ++k)
        x[c * i + k] += a * y[c * i + k];
    }
  };
  if (d == 3)
    run.template operator()<3>();
  else if (d == 2)
    run.template operator()<2>();
  else
    run.template operator()<1>();
}
} // namespace

template <int dim> void kick(ParticleStore<dim>& p, double h) {
  // v += (h/m) F, ω += (h/I) M over flat arrays (x, y[, z] per grain).
  constexpr int rd = rot_dim<dim>;
  static_assert(sizeof(Vec<dim>) == dim * sizeof(double) &&
                sizeof(RotVec<dim>) == rd * sizeof(double));
  const std::size_t n = p.n_owned();
  kick_flat(p.velocity.data()->data(), p.force.data()->data(), p.mass.data(), n, dim, h);
  kick_flat(p.angular_velocity.data()->data(), p.torque.data()->data(), p.inertia.data(), n, rd, h);
}

namespace {
/// q <- dq q renormalised, dq = (cw, sv u): the Hamilton product, q = (w, x, y, z).
inline void rotate_quaternion(double* q, double cw, double sv, double ux, double uy, double uz) {
  const double dx = sv * ux, dy = sv * uy, dz = sv * uz;
  const double qw = q[0], qx = q[1], qy = q[2], qz = q[3];
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

/// When every grain turns by less than 1e-3 rad (|u|² < 1e-6, u = ω dt/2: always, in MD),
/// turns all their orientations by the series of dq and returns true; otherwise changes
/// nothing and returns false. Branch-free over the grains: the compiler vectorises it (a
/// grain at rest gets dq = 1 and its q renormalised, which leaves a unit q unchanged).
GRANPACK_SIMD_CLONES
bool turn_on_series(double* o, const double* w, std::size_t n, double hdt) {
  double y2_max = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double ux = hdt * w[3 * i], uy = hdt * w[3 * i + 1], uz = hdt * w[3 * i + 2];
    y2_max = std::max(y2_max, ux * ux + uy * uy + uz * uz);
  }
  if (!(y2_max < kSmallAngleSquared))
    return false;
  for (std::size_t i = 0; i < n; ++i) {
    const double ux = hdt * w[3 * i], uy = hdt * w[3 * i + 1], uz = hdt * w[3 * i + 2];
    const double y2 = ux * ux + uy * uy + uz * uz;
    const SmallAngle a = small_angle_series(y2);
    rotate_quaternion(o + 4 * i, a.cos_x, a.sin_x_over_x, ux, uy, uz);
  }
  return true;
}
} // namespace

template <int dim> void drift(ParticleStore<dim>& p, const Cell<dim>& cell, double dt) {
  const std::size_t n = p.n_owned();
  const Vec<dim> inv_l = cell.length.cwiseInverse();
  double* s = p.position.data()->data();
  const double* v = p.velocity.data()->data();
  for (std::size_t i = 0; i < n; ++i)
    for (int k = 0; k < dim; ++k)
      s[dim * i + k] += dt * (v[dim * i + k] * inv_l[k]);
  if constexpr (dim == 3) {
    // q <- exp(dt omega / 2) q, renormalised: orientation is output only.
    // dq = (cos y, sin(y)/y u) with u = ω dt/2, y = |u|. For y < 1e-3 (always, in MD:
    // y ~ 1e-7) the Taylor series to y⁴ is exact to rounding and spares the square root,
    // sin and cos per grain and step.
    const double* w = p.angular_velocity.data()->data();
    double* o = p.orientation.data()->data();
    static_assert(sizeof(OrientVec<3>) == 4 * sizeof(double));
    const double hdt = 0.5 * dt;
    if (turn_on_series(o, w, n, hdt))
      return;
    for (std::size_t i = 0; i < n; ++i) {
      const double ux = hdt * w[3 * i], uy = hdt * w[3 * i + 1], uz = hdt * w[3 * i + 2];
      const double y2 = ux * ux + uy * uy + uz * uz;
      if (!(y2 > 0))
        continue;
      if (y2 < kSmallAngleSquared) {
        const SmallAngle a = small_angle_series(y2);
        rotate_quaternion(o + 4 * i, a.cos_x, a.sin_x_over_x, ux, uy, uz);
      } else {
        const double y = std::sqrt(y2);
        rotate_quaternion(o + 4 * i, std::cos(y), std::sin(y) / y, ux, uy, uz);
      }
    }
  } else {
    for (std::size_t i = 0; i < n; ++i)
      p.orientation[i][0] += dt * p.angular_velocity[i][0];
  }
}

template <int dim> Vec<dim> momentum(const ParticleStore<dim>& p) {
  Vec<dim> m = Vec<dim>::Zero();
  for (std::size_t i = 0; i < p.n_owned(); ++i)
    m += p.mass[i] * p.velocity[i];
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

} // namespace granpack
