#include "granpack/dynamics/contact_forces.h"

#include <algorithm>
#include <array>

namespace granpack {

template <int dim>
void ContactForceLoop<dim>::bind(const ParticleStore<dim>& p, const VerletList<dim>& list,
                                 ContactStore<dim>& store) {
  store.erase_if([](const ContactKey&, const ContactState<dim>& s) { return s.age == 0; });
  slot_.assign(list.n_pairs(), -1);
  if (store.size() == 0) {
    store.reserve(list.n_pairs()); // every contact until the next rebuild is a listed pair
    return;
  }
  const auto& off = list.offsets();
  const auto& nb = list.neighbor_array();
  std::size_t without = 0; // listed pairs with no contact yet: the contacts that may form
  for (std::size_t i = 0; i < list.n_owned(); ++i)
    for (std::size_t k = off[i]; k < off[i + 1]; ++k) {
      slot_[k] = store.find(ContactKey{p.id[i], p.id[nb[k]]});
      without += slot_[k] < 0 ? 1 : 0;
    }
  // Lay the histories out in list order (those of no listed pair, if any, after them): the
  // force loop then walks the store sequentially instead of jumping through it in insertion
  // order (72-byte records; a cache miss per contact once the store outgrows the L2 cache).
  std::vector<std::size_t> order;
  order.reserve(store.size());
  std::vector<std::ptrdiff_t> moved(store.size(), -1);
  for (auto& s : slot_) {
    if (s < 0)
      continue;
    if (moved[static_cast<std::size_t>(s)] < 0) {
      moved[static_cast<std::size_t>(s)] = static_cast<std::ptrdiff_t>(order.size());
      order.push_back(static_cast<std::size_t>(s));
    }
    s = moved[static_cast<std::size_t>(s)];
  }
  for (std::size_t k = 0; k < store.size(); ++k)
    if (moved[k] < 0)
      order.push_back(k);
  store.permute(order, store.size() + without);
}

namespace {

// compute_batched reads the particle arrays as x, y, z triples (x, y pairs and one ω in 2D).
static_assert(sizeof(Vec<3>) == 3 * sizeof(double) && sizeof(RotVec<3>) == 3 * sizeof(double));
static_assert(sizeof(Vec<2>) == 2 * sizeof(double) && sizeof(RotVec<2>) == sizeof(double));

/// Evaluates listed pair (i, j) with the scalar contact law and adds its forces, torques and
/// virial; `slot` is its contact in the store (inserted by the caller).
template <int dim>
[[gnu::always_inline]] inline void scalar_pair(System<dim>& sys, const ContactLaw<dim>& law,
                                               std::size_t i, std::size_t j, const Vec<dim>& ds,
                                               const Vec<dim>& r_ij, std::size_t slot, double dt,
                                               ForceSums<dim>& sums) {
  auto& p = sys.particles;
  ContactState<dim>& st = sys.contacts.state(slot);
  const double ri = p.radius[i];
  const auto g = make_pair_geometry<dim>(ri, p.radius[j], p.mass[i], p.mass[j], r_ij);
  ContactKinematics<dim> kin;
  kin.v_i = p.velocity[i];
  // Relative velocity includes the affine part of the cell deformation, Ldot (s_j - s_i).
  kin.v_j = p.velocity[j] + sys.cell.rate.cwiseProduct(ds);
  kin.w_i = p.angular_velocity[i];
  kin.w_j = p.angular_velocity[j];
  const ContactForces<dim> f = law.force(g, kin, st, dt);
  if (!f.active)
    return;
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

/// The first pass of the batched gather over grain i's row, list entries [k0, k1): tests the
/// distance of every listed j against R_i + R_j + range and writes the place in the row of
/// each pair in range to `hits`, advancing the count by `in_range` (no branch to mispredict on
/// the random contact/no-contact outcome); returns the count. The one branch, taken only when
/// a contact opens or forms (rare, well predicted): a pair that left the range has its history
/// reset (erased at the next compaction) and its slot cleared; one that entered it gets a
/// history. A listed pair out of range then costs its distance test and one store (the loose
/// phase, docs/performance.md).
template <int dim>
[[gnu::always_inline]] inline std::size_t
pairs_in_range(System<dim>& sys, std::size_t i, std::size_t k0, std::size_t k1,
               const std::uint32_t* nb, double range, std::ptrdiff_t* slots, std::uint32_t* hits) {
  // Raw pointers (contiguous components per grain): the compiler then knows they do not move.
  const double* pos = sys.particles.position.data()->data();
  const double* radius = sys.particles.radius.data();
  double L[dim], si[dim];
  for (int a = 0; a < dim; ++a) {
    L[a] = sys.cell.length[a];
    si[a] = pos[dim * i + a];
  }
  const double ri = radius[i];
  std::size_t m = 0;
  for (std::size_t k = k0; k < k1; ++k) {
    const std::size_t j = nb[k];
    double r2;
    if constexpr (dim == 3) {
      const double rx = L[0] * (pos[3 * j] - si[0]), ry = L[1] * (pos[3 * j + 1] - si[1]),
                   rz = L[2] * (pos[3 * j + 2] - si[2]);
      r2 = rx * rx + ry * ry + rz * rz;
    } else {
      const double rx = L[0] * (pos[2 * j] - si[0]), ry = L[1] * (pos[2 * j + 1] - si[1]);
      r2 = rx * rx + ry * ry;
    }
    const double reach = ri + radius[j] + range;
    const bool in_range = r2 < reach * reach;
    const std::ptrdiff_t slot = slots[k];
    if (__builtin_expect(in_range != (slot >= 0), 0)) {
      if (!in_range) {
        sys.contacts.state(static_cast<std::size_t>(slot)) = ContactState<dim>{};
        slots[k] = -1;
      } else {
        slots[k] = static_cast<std::ptrdiff_t>(sys.contacts.insert(
            ContactKey{sys.particles.id[i], sys.particles.id[j]}, ContactState<dim>{}));
      }
    }
    hits[m] = static_cast<std::uint32_t>(k - k0);
    m += in_range ? 1 : 0;
  }
  return m;
}

/// Adds what a batched kernel summed over its lanes (virials row-major, dim x dim) to the
/// loop's sums, which hold those of the lanes the scalar law evaluated.
template <int dim, class BatchSums>
void add_batch_sums(ForceSums<dim>& sums, const BatchSums& batch) {
  for (int a = 0; a < dim; ++a)
    for (int b = 0; b < dim; ++b) {
      sums.virial(a, b) += batch.virial[dim * a + b];
      sums.virial_elastic(a, b) += batch.virial_elastic[dim * a + b];
    }
  sums.max_overlap = std::max(sums.max_overlap, batch.max_overlap);
  sums.interacting += batch.contacts;
}

} // namespace

template <int dim>
ForceSums<dim> ContactForceLoop<dim>::compute(System<dim>& sys, const VerletList<dim>& list,
                                              const ContactLaw<dim>& law, double dt) {
  if constexpr (dim == 3) {
    if (const auto c = HertzMindlinConstants::of(law))
      return compute_batched(sys, list, law, *c, dt);
  } else {
    if (const auto c = DiskContactConstants::of(law))
      return compute_batched(sys, list, law, *c, dt);
  }
  auto& p = sys.particles;
  p.clear_forces();
  ForceSums<dim> sums;
  const Vec<dim> L = sys.cell.length;
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
        if (slot_[k] >= 0)
          sys.contacts.state(static_cast<std::size_t>(slot_[k])) = ContactState<dim>{};
        continue;
      }
      if (slot_[k] < 0)
        slot_[k] = static_cast<std::ptrdiff_t>(
            sys.contacts.insert(ContactKey{p.id[i], p.id[j]}, ContactState<dim>{}));
      scalar_pair<dim>(sys, law, i, j, ds, r_ij, static_cast<std::size_t>(slot_[k]), dt, sums);
    }
  }
  return sums;
}

template <int dim>
ForceSums<dim> ContactForceLoop<dim>::compute_batched(System<dim>& sys, const VerletList<dim>& list,
                                                      const ContactLaw<dim>& law,
                                                      const HertzMindlinConstants& c,
                                                      double dt) requires(dim == 3) {
  auto& p = sys.particles;
  p.clear_forces();
  ForceSums<dim> sums;
  HertzMindlinSums batch_sums;
  if (!batch_)
    batch_ = std::make_unique<HertzMindlinBatch>();
  HertzMindlinBatch& b = *batch_;
  constexpr std::size_t cap = HertzMindlinBatch::kCapacity;
  std::array<std::uint32_t, cap> lane_i{}, lane_j{};
  std::array<std::size_t, cap> lane_slot{};
  std::size_t n = 0;
  const Vec<3> L = sys.cell.length;
  const Vec<3> Ldot = sys.cell.rate;

  // Evaluates the gathered lanes, then adds their forces and torques in lane (= list) order,
  // the same order as the scalar loop.
  auto flush = [&] {
    if (n == 0)
      return;
    evaluate(c, b, n, dt, batch_sums);
    // Raw pointers: the compiler then knows the arrays do not move during the loop.
    double* force = p.force.data()->data();
    double* torque = p.torque.data()->data();
    ContactState<3>* states = &sys.contacts.state(0);
    for (std::size_t l = 0; l < n; ++l) {
      const std::size_t i = lane_i[l], j = lane_j[l];
      if (b.exact[l]) {
        // Off the batch's path: the scalar law, from the untouched stored state.
        const Vec<3> r_ij(b.rx[l], b.ry[l], b.rz[l]);
        scalar_pair<3>(sys, law, i, j, Vec<3>(p.position[j] - p.position[i]), r_ij, lane_slot[l],
                       dt, sums);
        continue;
      }
      ContactState<3>& st = states[lane_slot[l]];
      st.normal_force = b.n_old[l];
      st.tangential_force = Vec<3>(b.tx[l], b.ty[l], b.tz[l]);
      st.flags = (st.flags & ~static_cast<std::uint32_t>(kSliding | kDistant)) |
                 (b.sliding[l] ? static_cast<std::uint32_t>(kSliding) : 0u);
      ++st.age;
      const double f[3] = {b.fx[l], b.fy[l], b.fz[l]};
      const double tj[3] = {b.tjx[l], b.tjy[l], b.tjz[l]};
      const double tq[3] = {b.tix[l], b.tiy[l], b.tiz[l]};
      for (int a = 0; a < 3; ++a) {
        force[3 * j + a] += f[a];
        force[3 * i + a] -= f[a];
        torque[3 * i + a] += tq[a];
        torque[3 * j + a] += tj[a];
      }
    }
    n = 0;
  };

  // Gathers the touching pairs, row by row in two passes. The first (pairs_in_range) tests the
  // distance of every listed pair of grain i and keeps the touching ones' positions in the
  // row. The second fills one lane per touching pair. A listed pair that does not touch, most
  // of them in a loose packing (a compression's gas), then costs its distance test and one
  // store instead of a lane's 21 stores and the loads of its velocities and history. Same
  // lanes in the same order as a single pass, hence the same bits.
  const auto& off = list.offsets();
  const std::uint32_t* nb = list.neighbor_array().data();
  // Raw pointers (contiguous x, y, z per grain): the compiler then knows they do not move.
  const double* pos = p.position.data()->data();
  const double* vel = p.velocity.data()->data();
  const double* spin = p.angular_velocity.data()->data();
  const double* radius = p.radius.data();
  const double* mass = p.mass.data();
  std::ptrdiff_t* slots = slot_.data();
  const double Lx = L[0], Ly = L[1], Lz = L[2], Ldx = Ldot[0], Ldy = Ldot[1], Ldz = Ldot[2];
  for (std::size_t i = 0; i < list.n_owned(); ++i) {
    const std::size_t k0 = off[i], k1 = off[i + 1];
    if (row_hits_.size() < k1 - k0)
      row_hits_.resize(k1 - k0);
    std::uint32_t* hits = row_hits_.data();
    const std::size_t m = pairs_in_range<3>(sys, i, k0, k1, nb, 0.0, slots, hits);
    if (m == 0)
      continue;
    // Read only for touching pairs, which have a history by now (the store may have grown).
    const ContactState<3>* states = &sys.contacts.state(0);
    const double six = pos[3 * i], siy = pos[3 * i + 1], siz = pos[3 * i + 2];
    const double ri = radius[i];
    const double vix = vel[3 * i], viy = vel[3 * i + 1], viz = vel[3 * i + 2];
    const double wix = spin[3 * i], wiy = spin[3 * i + 1], wiz = spin[3 * i + 2];
    const double mi = mass[i];
    for (std::size_t t = 0; t < m; ++t) {
      const std::size_t k = k0 + hits[t];
      const std::size_t j = nb[k];
      // The same arithmetic as the first pass: the same r_ij.
      const double dsx = pos[3 * j] - six, dsy = pos[3 * j + 1] - siy, dsz = pos[3 * j + 2] - siz;
      const std::size_t slot = static_cast<std::size_t>(slots[k]);
      const ContactState<3>& st = states[slot];
      // The histories lie in list order (bind()): fetch a few contacts ahead, which the
      // hardware prefetcher, busy with the batch's streams, does not always do.
      __builtin_prefetch(&st + 8);
      b.rx[n] = Lx * dsx;
      b.ry[n] = Ly * dsy;
      b.rz[n] = Lz * dsz;
      b.rad_i[n] = ri;
      b.rad_j[n] = radius[j];
      b.mass_i[n] = mi;
      b.mass_j[n] = mass[j];
      // Relative velocity, with the affine part of the cell deformation Ldot (s_j - s_i).
      b.vx[n] = (vel[3 * j] + Ldx * dsx) - vix;
      b.vy[n] = (vel[3 * j + 1] + Ldy * dsy) - viy;
      b.vz[n] = (vel[3 * j + 2] + Ldz * dsz) - viz;
      b.wix[n] = wix;
      b.wiy[n] = wiy;
      b.wiz[n] = wiz;
      b.wjx[n] = spin[3 * j];
      b.wjy[n] = spin[3 * j + 1];
      b.wjz[n] = spin[3 * j + 2];
      b.tx[n] = st.tangential_force[0];
      b.ty[n] = st.tangential_force[1];
      b.tz[n] = st.tangential_force[2];
      b.n_old[n] = st.normal_force;
      lane_i[n] = static_cast<std::uint32_t>(i);
      lane_j[n] = static_cast<std::uint32_t>(j);
      lane_slot[n] = slot;
      if (++n == cap)
        flush();
    }
  }
  flush();
  add_batch_sums(sums, batch_sums);
  return sums;
}

template <int dim>
ForceSums<dim> ContactForceLoop<dim>::compute_batched(System<dim>& sys, const VerletList<dim>& list,
                                                      const ContactLaw<dim>& law,
                                                      const DiskContactConstants& c,
                                                      double dt) requires(dim == 2) {
  auto& p = sys.particles;
  p.clear_forces();
  ForceSums<dim> sums;
  DiskContactSums batch_sums;
  if (!disk_batch_)
    disk_batch_ = std::make_unique<DiskContactBatch>();
  DiskContactBatch& b = *disk_batch_;
  constexpr std::size_t cap = DiskContactBatch::kCapacity;
  std::array<std::uint32_t, cap> lane_i{}, lane_j{};
  std::array<std::size_t, cap> lane_slot{};
  std::size_t n = 0;
  // Without rolling resistance the law leaves kRollingPlastic as it was (never set).
  const std::uint32_t kept = c.rolling ? 0u : static_cast<std::uint32_t>(kRollingPlastic);

  // As in 3D: evaluates the gathered lanes, then adds their forces and torques in lane
  // (= list) order, the same order as the scalar loop.
  auto flush = [&] {
    if (n == 0)
      return;
    evaluate(c, b, n, dt, batch_sums);
    double* force = p.force.data()->data();
    double* torque = p.torque.data()->data();
    ContactState<2>* states = &sys.contacts.state(0);
    for (std::size_t l = 0; l < n; ++l) {
      const std::size_t i = lane_i[l], j = lane_j[l];
      if (b.exact[l]) {
        const Vec<2> r_ij(b.rx[l], b.ry[l]);
        scalar_pair<2>(sys, law, i, j, Vec<2>(p.position[j] - p.position[i]), r_ij, lane_slot[l],
                       dt, sums);
        continue;
      }
      ContactState<2>& st = states[lane_slot[l]];
      const auto flags = static_cast<std::uint32_t>(b.flags[l]);
      st.normal_force = b.n_old[l];
      st.tangential_force = Vec<2>(b.tx[l], b.ty[l]);
      st.rolling[0] = b.rolling[l];
      st.flags = flags | ((flags & kDistant) ? 0u : st.flags & kept);
      ++st.age;
      force[2 * j] += b.fx[l];
      force[2 * j + 1] += b.fy[l];
      force[2 * i] -= b.fx[l];
      force[2 * i + 1] -= b.fy[l];
      torque[i] += b.ti[l];
      torque[j] += b.tj[l];
    }
    n = 0;
  };

  // Two passes per row, as in 3D; the range includes the cohesion's D0, so that the lanes
  // hold the distant interactions too.
  const auto& off = list.offsets();
  const std::uint32_t* nb = list.neighbor_array().data();
  const double* pos = p.position.data()->data();
  const double* vel = p.velocity.data()->data();
  const double* spin = p.angular_velocity.data()->data();
  const double* radius = p.radius.data();
  const double* mass = p.mass.data();
  std::ptrdiff_t* slots = slot_.data();
  const double Lx = sys.cell.length[0], Ly = sys.cell.length[1];
  const double Ldx = sys.cell.rate[0], Ldy = sys.cell.rate[1];
  const double range = law.interaction_range();
  for (std::size_t i = 0; i < list.n_owned(); ++i) {
    const std::size_t k0 = off[i], k1 = off[i + 1];
    if (row_hits_.size() < k1 - k0)
      row_hits_.resize(k1 - k0);
    std::uint32_t* hits = row_hits_.data();
    const std::size_t m = pairs_in_range<2>(sys, i, k0, k1, nb, range, slots, hits);
    if (m == 0)
      continue;
    const ContactState<2>* states = &sys.contacts.state(0);
    const double six = pos[2 * i], siy = pos[2 * i + 1];
    const double ri = radius[i], mi = mass[i];
    const double vix = vel[2 * i], viy = vel[2 * i + 1], wi = spin[i];
    for (std::size_t t = 0; t < m; ++t) {
      const std::size_t k = k0 + hits[t];
      const std::size_t j = nb[k];
      const double dsx = pos[2 * j] - six, dsy = pos[2 * j + 1] - siy;
      const std::size_t slot = static_cast<std::size_t>(slots[k]);
      const ContactState<2>& st = states[slot];
      __builtin_prefetch(&st + 8);
      b.rx[n] = Lx * dsx;
      b.ry[n] = Ly * dsy;
      b.rad_i[n] = ri;
      b.rad_j[n] = radius[j];
      b.mass_i[n] = mi;
      b.mass_j[n] = mass[j];
      b.vx[n] = (vel[2 * j] + Ldx * dsx) - vix;
      b.vy[n] = (vel[2 * j + 1] + Ldy * dsy) - viy;
      b.wi[n] = wi;
      b.wj[n] = spin[j];
      b.tx[n] = st.tangential_force[0];
      b.ty[n] = st.tangential_force[1];
      b.n_old[n] = st.normal_force;
      b.rolling[n] = st.rolling[0];
      lane_i[n] = static_cast<std::uint32_t>(i);
      lane_j[n] = static_cast<std::uint32_t>(j);
      lane_slot[n] = slot;
      if (++n == cap)
        flush();
    }
  }
  flush();
  add_batch_sums(sums, batch_sums);
  return sums;
}

template <int dim>
void ContactForceLoop<dim>::elastic_forces(const System<dim>& sys, const VerletList<dim>& list,
                                           const ContactLaw<dim>& law, std::vector<Vec<dim>>& out,
                                           std::vector<RotVec<dim>>* moments) const {
  out.assign(sys.particles.size(), Vec<dim>::Zero());
  if (moments)
    moments->assign(sys.particles.size(), RotVec<dim>::Zero());
  const auto& radius = sys.particles.radius;
  const double k_r = law.rolling ? law.rolling->k_r : 0.0;
  for_each_contact(
      sys, list, [&](std::size_t i, std::size_t j, const Vec<dim>& r, const ContactState<dim>& st) {
        const double d = r.norm();
        const double h = radius[i] + radius[j] - d;
        const Vec<dim> n = r / d;
        const Vec<dim> f = (st.normal_force + law.attraction(h)) * n + st.tangential_force;
        out[j] += f;
        out[i] -= f;
        if (!moments)
          return;
        // Branch vectors to the middle of the overlap, as in ContactLaw::force (for a distant
        // pair f is along n and its moments vanish whatever the branch).
        const RotVec<dim> gamma = -k_r * st.rolling; // rolling moment on j
        (*moments)[j] += moment<dim>(Vec<dim>(-contact_arm(radius[j], h) * n), f) + gamma;
        (*moments)[i] += moment<dim>(Vec<dim>(contact_arm(radius[i], h) * n), Vec<dim>(-f)) - gamma;
      });
}

template class ContactForceLoop<2>;
template class ContactForceLoop<3>;

} // namespace granpack
