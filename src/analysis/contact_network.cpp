#include "granpack/analysis/contact_network.h"

#include <cmath>
#include <numbers>
#include <unordered_map>

#include "granpack/contact/pair_geometry.h"

namespace granpack {

template <int dim>
NetworkFields<dim> contact_network(const Cell<dim>& cell, const ParticleStore<dim>& p,
                                   const ContactStore<dim>& contacts, const ContactLaw<dim>& law) {
  NetworkFields<dim> f;
  const std::size_t nc = contacts.size(), n = p.size();
  f.reset(nc, n);
  const double k_r = law.rolling ? law.rolling->k_r : 0.0;
  // Local index of each id: the owned copy first (emplace keeps it), else any ghost image.
  std::unordered_map<GlobalId, std::size_t> index;
  index.reserve(n);
  for (std::size_t i = 0; i < n; ++i)
    index.emplace(p.id[i], i);
  for (std::size_t k = 0; k < nc; ++k) {
    const auto key = contacts.key(k);
    const auto a = index.find(key.first), b = index.find(key.second);
    if (a == index.end() || b == index.end()) {
      ++f.missing;
      continue;
    }
    const std::size_t i = a->second, j = b->second;
    const auto& s = contacts.state(k);
    const Vec<dim> r = cell.min_image(p.position[i], p.position[j]);
    const double dist = r.norm();
    const Vec<dim> normal = dist > 0 ? Vec<dim>(r / dist) : Vec<dim>::Zero();
    const bool distant = (s.flags & kDistant) != 0;
    const double h = p.radius[i] + p.radius[j] - dist;
    const double force = s.normal_force + law.attraction(h);
    f.start[k] = cell.to_real(Cell<dim>::wrap(p.position[i]));
    f.end[k] = f.start[k] + r;
    f.normal_force[k] = force;
    f.tangential_magnitude[k] = s.tangential_force.norm();
    f.pairs.push_back({i, j, s.normal_force});
    const double limit = coulomb_limit(law.friction.mu, s.normal_force);
    f.mobilisation[k] = limit > 0 && std::isfinite(limit) ? f.tangential_magnitude[k] / limit : 0.0;
    f.kind[k] = static_cast<std::int64_t>(distant     ? NetworkKind::kDistant
                                          : force > 0 ? NetworkKind::kCompressive
                                          : force < 0 ? NetworkKind::kTensile
                                                      : NetworkKind::kUnstressed);
    if (!distant) {
      f.contacts[i] += 1;
      f.contacts[j] += 1;
    }
    if (!distant && s.normal_force > 0) {
      f.carrying_contacts[i] += 1;
      f.carrying_contacts[j] += 1;
    }
    const Vec<dim> on_second = force * normal + s.tangential_force; // docs/hdf5-schema.md
    for (int c = 0; c < dim; ++c) {
      f.net_force[c][j] += on_second[c];
      f.net_force[c][i] -= on_second[c];
    }
    // Moments about the centres, the force applied at the middle of the overlap (for a
    // distant pair f is along n and its moments vanish whatever the arm), as the engine's
    // elastic_forces(): contact_forces.cpp.
    const RotVec<dim> gamma = -k_r * s.rolling; // rolling moment on `second`
    const RotVec<dim> m_j = moment<dim>(Vec<dim>(-contact_arm(p.radius[j], h) * normal), on_second);
    const RotVec<dim> m_i =
        moment<dim>(Vec<dim>(contact_arm(p.radius[i], h) * normal), Vec<dim>(-on_second));
    for (int c = 0; c < rot_dim<dim>; ++c) {
      f.net_moment[std::size_t(c)][j] += m_j[c] + gamma[c];
      f.net_moment[std::size_t(c)][i] += m_i[c] - gamma[c];
    }
    const double half_virial = 0.5 * on_second.dot(r); // each grain's share of f.r_12
    f.mean_stress[i] += half_virial / (dim * grain_volume<dim>(p.radius[i]));
    f.mean_stress[j] += half_virial / (dim * grain_volume<dim>(p.radius[j]));
    // The tensor the same way: half of f (x) r_12 to each grain, over its own volume.
    const double vi = grain_volume<dim>(p.radius[i]), vj = grain_volume<dim>(p.radius[j]);
    for (int row = 0; row < dim; ++row)
      for (int col = 0; col < dim; ++col) {
        const double half = 0.5 * on_second[row] * r[col];
        f.stress[row * dim + col][i] += half / vi;
        f.stress[row * dim + col][j] += half / vj;
      }
  }
  return f;
}

template NetworkFields<2> contact_network<2>(const Cell<2>&, const ParticleStore<2>&,
                                             const ContactStore<2>&, const ContactLaw<2>&);
template NetworkFields<3> contact_network<3>(const Cell<3>&, const ParticleStore<3>&,
                                             const ContactStore<3>&, const ContactLaw<3>&);

} // namespace granpack
