#include "granpack/dynamics/contact_forces.h"

#include <algorithm>

namespace granpack {

template <int dim>
void ContactForceLoop<dim>::bind(const ParticleStore<dim>& p, const VerletList<dim>& list,
                                 ContactStore<dim>& store) {
  store.erase_if([](const ContactKey&, const ContactState<dim>& s) { return s.age == 0; });
  slot_.assign(list.n_pairs(), -1);
  if (store.size() == 0) return;
  const auto& off = list.offsets();
  const auto& nb = list.neighbor_array();
  for (std::size_t i = 0; i < list.n_owned(); ++i)
    for (std::size_t k = off[i]; k < off[i + 1]; ++k)
      slot_[k] = store.find(ContactKey{p.id[i], p.id[nb[k]]});
  // Lay the histories out in list order (those of no listed pair, if any, after them): the
  // force loop then walks the store sequentially instead of jumping through it in insertion
  // order (72-byte records; a cache miss per contact once the store outgrows the L2 cache).
  std::vector<std::size_t> order;
  order.reserve(store.size());
  std::vector<std::ptrdiff_t> moved(store.size(), -1);
  for (auto& s : slot_) {
    if (s < 0) continue;
    if (moved[static_cast<std::size_t>(s)] < 0) {
      moved[static_cast<std::size_t>(s)] = static_cast<std::ptrdiff_t>(order.size());
      order.push_back(static_cast<std::size_t>(s));
    }
    s = moved[static_cast<std::size_t>(s)];
  }
  for (std::size_t k = 0; k < store.size(); ++k)
    if (moved[k] < 0) order.push_back(k);
  store.permute(order);
}

template <int dim>
ForceSums<dim> ContactForceLoop<dim>::compute(System<dim>& sys, const VerletList<dim>& list,
                                              const ContactLaw<dim>& law, double dt) {
  auto& p = sys.particles;
  p.clear_forces();
  ForceSums<dim> sums;
  const Vec<dim> L = sys.cell.length;
  const Vec<dim> Ldot = sys.cell.rate;
  const double range = law.interaction_range();
  const auto& off = list.offsets();
  const auto& nb = list.neighbor_array();
  for (std::size_t i = 0; i < list.n_owned(); ++i) {
    const Vec<dim> si = p.position[i];
    const double ri = p.radius[i];
    for (std::size_t k = off[i]; k < off[i + 1]; ++k) {
      const std::size_t j = nb[k];
      const Vec<dim> ds = p.position[j] - si;
      const Vec<dim> r_ij = L.cwiseProduct(ds);
      const double reach = ri + p.radius[j] + range;
      if (r_ij.squaredNorm() >= reach * reach) {
        // Out of reach: a contact that was there has ended; its history is forgotten.
        if (slot_[k] >= 0) sys.contacts.state(static_cast<std::size_t>(slot_[k])) = ContactState<dim>{};
        continue;
      }
      if (slot_[k] < 0)
        slot_[k] = static_cast<std::ptrdiff_t>(
            sys.contacts.insert(ContactKey{p.id[i], p.id[j]}, ContactState<dim>{}));
      ContactState<dim>& st = sys.contacts.state(static_cast<std::size_t>(slot_[k]));
      const auto g = make_pair_geometry<dim>(ri, p.radius[j], p.mass[i], p.mass[j], r_ij);
      ContactKinematics<dim> kin;
      kin.v_i = p.velocity[i];
      // Relative velocity includes the affine part of the cell deformation, Ldot (s_j - s_i).
      kin.v_j = p.velocity[j] + Ldot.cwiseProduct(ds);
      kin.w_i = p.angular_velocity[i];
      kin.w_j = p.angular_velocity[j];
      const ContactForces<dim> f = law.force(g, kin, st, dt);
      if (!f.active) continue;
      p.force[j] += f.force_on_j;
      p.force[i] -= f.force_on_j;
      p.torque[i] += f.torque_i;
      p.torque[j] += f.torque_j;
      sums.virial.noalias() += f.force_on_j * r_ij.transpose();
      sums.virial_elastic.noalias() +=
          ((f.normal_elastic + f.normal_attractive) * g.normal + f.tangential) * r_ij.transpose();
      ++sums.interacting;
      // max of h / min(R_i, R_j), dividing only when the maximum may change
      const double r_min = std::min(ri, p.radius[j]);
      if (g.overlap > sums.max_overlap * r_min)
        sums.max_overlap = std::max(sums.max_overlap, g.overlap / r_min);
    }
  }
  return sums;
}

template <int dim>
void ContactForceLoop<dim>::elastic_forces(const System<dim>& sys, const VerletList<dim>& list,
                                           const ContactLaw<dim>& law,
                                           std::vector<Vec<dim>>& out,
                                           std::vector<RotVec<dim>>* moments) const {
  out.assign(sys.particles.size(), Vec<dim>::Zero());
  if (moments) moments->assign(sys.particles.size(), RotVec<dim>::Zero());
  const auto& radius = sys.particles.radius;
  const double k_r = law.rolling ? law.rolling->k_r : 0.0;
  for_each_contact(sys, list, [&](std::size_t i, std::size_t j, const Vec<dim>& r,
                                  const ContactState<dim>& st) {
    const double d = r.norm();
    const double h = radius[i] + radius[j] - d;
    const Vec<dim> n = r / d;
    const Vec<dim> f = (st.normal_force + law.attraction(h)) * n + st.tangential_force;
    out[j] += f;
    out[i] -= f;
    if (!moments) return;
    // Branch vectors to the middle of the overlap, as in ContactLaw::force (for a distant
    // pair f is along n and its moments vanish whatever the branch).
    const RotVec<dim> gamma = -k_r * st.rolling;  // rolling moment on j
    (*moments)[j] += moment<dim>(Vec<dim>(-(radius[j] - 0.5 * h) * n), f) + gamma;
    (*moments)[i] += moment<dim>(Vec<dim>((radius[i] - 0.5 * h) * n), Vec<dim>(-f)) - gamma;
  });
}

template class ContactForceLoop<2>;
template class ContactForceLoop<3>;

}  // namespace granpack
