#include "granpack/comm/particle_packing.h"

namespace granpack {

template <int dim>
void Packing<dim>::pack_particle(const ParticleStore<dim>& p, std::size_t i,
                                 std::vector<double>& buf) {
  buf.push_back(static_cast<double>(p.id[i]));
  buf.push_back(p.radius[i]);
  buf.push_back(p.mass[i]);
  buf.push_back(p.inertia[i]);
  for (int a = 0; a < dim; ++a)
    buf.push_back(p.position[i][a]);
  for (int a = 0; a < dim; ++a)
    buf.push_back(p.velocity[i][a]);
  for (int a = 0; a < rot_dim<dim>; ++a)
    buf.push_back(p.angular_velocity[i][a]);
  for (int a = 0; a < orient_dim<dim>; ++a)
    buf.push_back(p.orientation[i][a]);
}

template <int dim>
Particle<dim> Packing<dim>::unpack_particle(const double* buf, std::size_t& pos) {
  Particle<dim> q;
  q.id = static_cast<GlobalId>(buf[pos++]);
  q.radius = buf[pos++];
  q.mass = buf[pos++];
  q.inertia = buf[pos++];
  for (int a = 0; a < dim; ++a)
    q.position[a] = buf[pos++];
  for (int a = 0; a < dim; ++a)
    q.velocity[a] = buf[pos++];
  for (int a = 0; a < rot_dim<dim>; ++a)
    q.angular_velocity[a] = buf[pos++];
  for (int a = 0; a < orient_dim<dim>; ++a)
    q.orientation[a] = buf[pos++];
  return q;
}

template <int dim>
void Packing<dim>::pack_contact(const ContactKey& k, const ContactState<dim>& s,
                                std::vector<double>& buf) {
  buf.push_back(static_cast<double>(k.first));
  buf.push_back(static_cast<double>(k.second));
  buf.push_back(s.normal_force);
  for (int a = 0; a < dim; ++a)
    buf.push_back(s.tangential_force[a]);
  for (int a = 0; a < rot_dim<dim>; ++a)
    buf.push_back(s.rolling[a]);
  buf.push_back(static_cast<double>(s.flags));
  buf.push_back(static_cast<double>(s.age));
}

template <int dim>
void Packing<dim>::unpack_contact(const double* buf, std::size_t& pos, ContactKey& k,
                                  ContactState<dim>& s) {
  k.first = static_cast<GlobalId>(buf[pos++]);
  k.second = static_cast<GlobalId>(buf[pos++]);
  s.normal_force = buf[pos++];
  for (int a = 0; a < dim; ++a)
    s.tangential_force[a] = buf[pos++];
  for (int a = 0; a < rot_dim<dim>; ++a)
    s.rolling[a] = buf[pos++];
  s.flags = static_cast<std::uint32_t>(buf[pos++]);
  s.age = static_cast<std::int64_t>(buf[pos++]);
}

template struct Packing<2>;
template struct Packing<3>;

} // namespace granpack
