#include "granpack/dynamics/integrator.h"

#include <Eigen/Geometry>
#include <cmath>

namespace granpack {

template <int dim> void kick(ParticleStore<dim>& p, double h) {
  const std::size_t n = p.n_owned();
  for (std::size_t i = 0; i < n; ++i) {
    p.velocity[i] += (h / p.mass[i]) * p.force[i];
    p.angular_velocity[i] += (h / p.inertia[i]) * p.torque[i];
  }
}

template <int dim> void drift(ParticleStore<dim>& p, const Cell<dim>& cell, double dt) {
  const std::size_t n = p.n_owned();
  const Vec<dim> inv_l = cell.length.cwiseInverse();
  for (std::size_t i = 0; i < n; ++i) {
    p.position[i] += dt * p.velocity[i].cwiseProduct(inv_l);
    if constexpr (dim == 3) {
      // q <- exp(dt omega / 2) q, renormalised: orientation is output only.
      // dq = (cos y, sin(y)/y v) with v = ω dt/2, y = |v|. For y < 1e-3 (always, in MD:
      // y ~ 1e-7) the Taylor series to y⁴ is exact to rounding and spares the square root,
      // sin and cos per grain and step.
      const Vec<3> v = (0.5 * dt) * p.angular_velocity[i];
      const double y2 = v.squaredNorm();
      if (y2 > 0) {
        Eigen::Quaterniond dq;
        if (y2 < 1e-6) {
          dq.w() = 1.0 - y2 * (1.0 / 2.0 - y2 * (1.0 / 24.0));
          dq.vec() = (1.0 - y2 * (1.0 / 6.0 - y2 * (1.0 / 120.0))) * v;
        } else {
          const double y = std::sqrt(y2);
          dq.w() = std::cos(y);
          dq.vec() = (std::sin(y) / y) * v;
        }
        auto& o = p.orientation[i];
        Eigen::Quaterniond q(o[0], o[1], o[2], o[3]);
        q = (dq * q).normalized();
        o = OrientVec<3>(q.w(), q.x(), q.y(), q.z());
      }
    } else {
      p.orientation[i][0] += dt * p.angular_velocity[i][0];
    }
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
