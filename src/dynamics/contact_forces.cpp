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

/// What compute_batched gathers from: the particle arrays as raw pointers (contiguous
/// components per grain) and the cell's length and rate, copied into members of a local
/// object, so that the compiler knows the lane stores change none of them.
template <int dim> struct GatherArrays {
  const double *pos, *vel, *spin, *radius, *mass;
  double L[dim], Ldot[dim];

  GatherArrays(const System<dim>& sys)
      : pos(sys.particles.position.data()->data()), vel(sys.particles.velocity.data()->data()),
        spin(sys.particles.angular_velocity.data()->data()), radius(sys.particles.radius.data()),
        mass(sys.particles.mass.data()) {
    for (int a = 0; a < dim; ++a) {
      L[a] = sys.cell.length[a];
      Ldot[a] = sys.cell.rate[a];
    }
  }
};

/// What compute_batched does differently for HertzMindlinBatch (3D, touching pairs only): how
/// a lane is filled from a pair and its history, and how its results go back.
struct HertzMindlinLanes {
  using Batch = HertzMindlinBatch;
  using Sums = HertzMindlinSums;
  static constexpr int dim = 3;
  const HertzMindlinConstants& c;

  double range(const ContactLaw<3>&) const { return 0.0; }
  void evaluate(Batch& b, std::size_t n, double dt, Sums& sums) const {
    granpack::evaluate(c, b, n, dt, sums);
  }
  static Vec<3> r_ij(const Batch& b, std::size_t l) { return {b.rx[l], b.ry[l], b.rz[l]}; }

  /// Grain i's values, loaded once per row; fill() writes lane n for the pair (i, j).
  struct Row {
    const GatherArrays<3> a;
    double six, siy, siz, ri, vix, viy, viz, wix, wiy, wiz, mi;
    Row(const System<3>& sys, std::size_t i)
        : a(sys), six(a.pos[3 * i]), siy(a.pos[3 * i + 1]), siz(a.pos[3 * i + 2]), ri(a.radius[i]),
          vix(a.vel[3 * i]), viy(a.vel[3 * i + 1]), viz(a.vel[3 * i + 2]), wix(a.spin[3 * i]),
          wiy(a.spin[3 * i + 1]), wiz(a.spin[3 * i + 2]), mi(a.mass[i]) {}
    void fill(Batch& b, std::size_t n, std::size_t j, const ContactState<3>& st) const {
      // The same arithmetic as pairs_in_range: the same r_ij.
      const double dsx = a.pos[3 * j] - six, dsy = a.pos[3 * j + 1] - siy,
                   dsz = a.pos[3 * j + 2] - siz;
      b.rx[n] = a.L[0] * dsx;
      b.ry[n] = a.L[1] * dsy;
      b.rz[n] = a.L[2] * dsz;
      b.rad_i[n] = ri;
      b.rad_j[n] = a.radius[j];
      b.mass_i[n] = mi;
      b.mass_j[n] = a.mass[j];
      // Relative velocity, with the affine part of the cell deformation Ldot (s_j - s_i).
      b.vx[n] = (a.vel[3 * j] + a.Ldot[0] * dsx) - vix;
      b.vy[n] = (a.vel[3 * j + 1] + a.Ldot[1] * dsy) - viy;
      b.vz[n] = (a.vel[3 * j + 2] + a.Ldot[2] * dsz) - viz;
      b.wix[n] = wix;
      b.wiy[n] = wiy;
      b.wiz[n] = wiz;
      b.wjx[n] = a.spin[3 * j];
      b.wjy[n] = a.spin[3 * j + 1];
      b.wjz[n] = a.spin[3 * j + 2];
      b.tx[n] = st.tangential_force[0];
      b.ty[n] = st.tangential_force[1];
      b.tz[n] = st.tangential_force[2];
      b.n_old[n] = st.normal_force;
    }
  };

  /// Writes lane l's new history to `st` and adds its forces and torques to i and j.
  void scatter(const Batch& b, std::size_t l, ContactState<3>& st, std::size_t i, std::size_t j,
               double* force, double* torque) const {
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
};

/// The same for DiskContactBatch (2D [GRC] law): the pairs in range include those across a
/// gap shorter than the cohesion's D0, and the history holds the rolling rotation too.
struct DiskContactLanes {
  using Batch = DiskContactBatch;
  using Sums = DiskContactSums;
  static constexpr int dim = 2;
  const DiskContactConstants& c;
  /// The flags a contact keeps from its history: without rolling resistance the law leaves
  /// kRollingPlastic as it was (never set).
  const std::uint32_t kept = c.rolling ? 0u : static_cast<std::uint32_t>(kRollingPlastic);

  double range(const ContactLaw<2>& law) const { return law.interaction_range(); }
  void evaluate(Batch& b, std::size_t n, double dt, Sums& sums) const {
    granpack::evaluate(c, b, n, dt, sums);
  }
  static Vec<2> r_ij(const Batch& b, std::size_t l) { return {b.rx[l], b.ry[l]}; }

  struct Row {
    const GatherArrays<2> a;
    double six, siy, ri, mi, vix, viy, wi;
    Row(const System<2>& sys, std::size_t i)
        : a(sys), six(a.pos[2 * i]), siy(a.pos[2 * i + 1]), ri(a.radius[i]), mi(a.mass[i]),
          vix(a.vel[2 * i]), viy(a.vel[2 * i + 1]), wi(a.spin[i]) {}
    void fill(Batch& b, std::size_t n, std::size_t j, const ContactState<2>& st) const {
      const double dsx = a.pos[2 * j] - six, dsy = a.pos[2 * j + 1] - siy;
      b.rx[n] = a.L[0] * dsx;
      b.ry[n] = a.L[1] * dsy;
      b.rad_i[n] = ri;
      b.rad_j[n] = a.radius[j];
      b.mass_i[n] = mi;
      b.mass_j[n] = a.mass[j];
      b.vx[n] = (a.vel[2 * j] + a.Ldot[0] * dsx) - vix;
      b.vy[n] = (a.vel[2 * j + 1] + a.Ldot[1] * dsy) - viy;
      b.wi[n] = wi;
      b.wj[n] = a.spin[j];
      b.tx[n] = st.tangential_force[0];
      b.ty[n] = st.tangential_force[1];
      b.n_old[n] = st.normal_force;
      b.rolling[n] = st.rolling[0];
    }
  };

  void scatter(const Batch& b, std::size_t l, ContactState<2>& st, std::size_t i, std::size_t j,
               double* force, double* torque) const {
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
};

} // namespace

template <int dim>
ForceSums<dim> ContactForceLoop<dim>::compute(System<dim>& sys, const VerletList<dim>& list,
                                              const ContactLaw<dim>& law, double dt) {
  if constexpr (dim == 3) {
    if (const auto c = HertzMindlinConstants::of(law)) {
      if (!batch_)
        batch_ = std::make_unique<HertzMindlinBatch>();
      return compute_batched(sys, list, law, HertzMindlinLanes{*c}, *batch_, dt);
    }
  } else {
    if (const auto c = DiskContactConstants::of(law)) {
      if (!disk_batch_)
        disk_batch_ = std::make_unique<DiskContactBatch>();
      return compute_batched(sys, list, law, DiskContactLanes{*c}, *disk_batch_, dt);
    }
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
template <class Lanes>
ForceSums<dim> ContactForceLoop<dim>::compute_batched(System<dim>& sys, const VerletList<dim>& list,
                                                      const ContactLaw<dim>& law,
                                                      const Lanes& lanes, typename Lanes::Batch& b,
                                                      double dt) {
  static_assert(Lanes::dim == dim);
  auto& p = sys.particles;
  p.clear_forces();
  ForceSums<dim> sums;
  typename Lanes::Sums batch_sums;
  constexpr std::size_t cap = Lanes::Batch::kCapacity;
  std::array<std::uint32_t, cap> lane_i{}, lane_j{};
  std::array<std::size_t, cap> lane_slot{};
  std::size_t n = 0;

  // Evaluates the gathered lanes, then adds their forces and torques in lane (= list) order,
  // the same order as the scalar loop.
  auto flush = [&] {
    if (n == 0)
      return;
    lanes.evaluate(b, n, dt, batch_sums);
    // Raw pointers: the compiler then knows the arrays do not move during the loop.
    double* force = p.force.data()->data();
    double* torque = p.torque.data()->data();
    ContactState<dim>* states = &sys.contacts.state(0);
    for (std::size_t l = 0; l < n; ++l) {
      const std::size_t i = lane_i[l], j = lane_j[l];
      if (b.exact[l]) {
        // Off the batch's path: the scalar law, from the untouched stored state.
        scalar_pair<dim>(sys, law, i, j, Vec<dim>(p.position[j] - p.position[i]), Lanes::r_ij(b, l),
                         lane_slot[l], dt, sums);
        continue;
      }
      lanes.scatter(b, l, states[lane_slot[l]], i, j, force, torque);
    }
    n = 0;
  };

  // Gathers the pairs in range, row by row in two passes. The first (pairs_in_range) tests the
  // distance of every listed pair of grain i and keeps the place in the row of those in range
  // (touching, or in 2D across a gap shorter than the cohesion's D0). The second fills one
  // lane per pair in range. A listed pair out of range, most of them in a loose packing (a
  // compression's gas), then costs its distance test and one store instead of a lane's ~20
  // stores and the loads of its velocities and history. Same lanes in the same order as a
  // single pass, hence the same bits.
  const auto& off = list.offsets();
  const std::uint32_t* nb = list.neighbor_array().data();
  std::ptrdiff_t* slots = slot_.data();
  const double range = lanes.range(law);
  for (std::size_t i = 0; i < list.n_owned(); ++i) {
    const std::size_t k0 = off[i], k1 = off[i + 1];
    if (row_hits_.size() < k1 - k0)
      row_hits_.resize(k1 - k0);
    std::uint32_t* hits = row_hits_.data();
    const std::size_t m = pairs_in_range<dim>(sys, i, k0, k1, nb, range, slots, hits);
    if (m == 0)
      continue;
    // Read only for pairs in range, which have a history by now (the store may have grown).
    const ContactState<dim>* states = &sys.contacts.state(0);
    const typename Lanes::Row row(sys, i);
    for (std::size_t t = 0; t < m; ++t) {
      const std::size_t k = k0 + hits[t];
      const std::size_t j = nb[k];
      const std::size_t slot = static_cast<std::size_t>(slots[k]);
      const ContactState<dim>& st = states[slot];
      // The histories lie in list order (bind()): fetch a few contacts ahead, which the
      // hardware prefetcher, busy with the batch's streams, does not always do.
      __builtin_prefetch(&st + 8);
      row.fill(b, n, j, st);
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
