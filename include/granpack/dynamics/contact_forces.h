#pragma once
// The force loop: every pair of the Verlet list is evaluated once with the contact law, the
// forces and torques are added to both grains (ghosts included: the comm layer sends ghost
// contributions back to their owners), and the stress virial is accumulated.
//
// Contact histories live in the ContactStore (keyed by global ids). To keep hash look-ups out
// of the hot loop, each Verlet pair caches the index of its contact in the store; the cache is
// rebuilt after every list rebuild (bind()), right after the store was compacted. Contacts
// that stop interacting are reset in place (age 0) and erased at the next compaction.
// MPI-free.
#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <vector>

#include "granpack/contact/contact_law.h"
#include "granpack/core/system.h"
#include "granpack/dynamics/disk_contact_batch.h"
#include "granpack/dynamics/hertz_mindlin_batch.h"
#include "granpack/neighbor/verlet_list.h"

namespace granpack {

/// What one force evaluation measured on this rank's pairs.
template <int dim> struct ForceSums {
  Tensor<dim> virial = Tensor<dim>::Zero();         ///< sum F_ij (x) r_ij, all contact forces
  Tensor<dim> virial_elastic = Tensor<dim>::Zero(); ///< the same with elastic forces only
  std::int64_t interacting = 0;                     ///< pairs in contact
  double max_overlap = 0;                           ///< largest h / min(R_i, R_j)
};

template <int dim> class ContactForceLoop {
public:
  /// Drops reset contacts from the store and caches, for every pair of the freshly built
  /// list, the index of its contact (or -1). Call after every list rebuild.
  void bind(const ParticleStore<dim>& p, const VerletList<dim>& list, ContactStore<dim>& store);

  /// Zeroes forces/torques, then evaluates every listed pair over a step dt.
  ForceSums<dim> compute(System<dim>& sys, const VerletList<dim>& list, const ContactLaw<dim>& law,
                         double dt);

  /// Static contact force on each local particle (owned + ghost, ghosts still to be reduced
  /// by the caller): F^el = (N^e + N^a) n + T of the stored states, N^a the cohesive
  /// attraction (viscous forces left out). With `moments`, also the static moment on each
  /// grain: the branch vectors' moments of F^el plus the rolling moments -/+ K_r δθ.
  /// For the equilibrium criteria.
  void elastic_forces(const System<dim>& sys, const VerletList<dim>& list,
                      const ContactLaw<dim>& law, std::vector<Vec<dim>>& out,
                      std::vector<RotVec<dim>>* moments = nullptr) const;

  /// Calls f(i, j, r_ij, state) for every interacting pair (state.age > 0: contacts and, with
  /// cohesion, distant interactions flagged kDistant); r_ij is the centre-to-centre vector.
  template <class F>
  void for_each_contact(const System<dim>& sys, const VerletList<dim>& list, F&& f) const;

private:
  /// compute() for the laws a batch kernel evaluates (3D Hertz-Mindlin without cohesion or
  /// rolling: HertzMindlinBatch; 2D [GRC] laws: DiskContactBatch): the pairs in range are
  /// gathered into batches, evaluated several per instruction, and their results added in
  /// list order. `Lanes` (contact_forces.cpp) says how a batch's lanes are filled and emptied.
  template <class Lanes>
  ForceSums<dim> compute_batched(System<dim>& sys, const VerletList<dim>& list,
                                 const ContactLaw<dim>& law, const Lanes& lanes,
                                 typename Lanes::Batch& b, double dt);

  std::vector<std::ptrdiff_t> slot_;         ///< per listed pair: index in the ContactStore or -1
  std::unique_ptr<HertzMindlinBatch> batch_; ///< scratch of compute_batched (~40 kB)
  std::unique_ptr<DiskContactBatch> disk_batch_; ///< scratch of the 2D compute_batched (~26 kB)
  std::vector<std::uint32_t> row_hits_; ///< scratch of compute_batched: one row's pairs in range
};

template <int dim>
template <class F>
void ContactForceLoop<dim>::for_each_contact(const System<dim>& sys, const VerletList<dim>& list,
                                             F&& f) const {
  const auto& p = sys.particles;
  const auto& off = list.offsets();
  const auto& nb = list.neighbor_array();
  for (std::size_t i = 0; i < list.n_owned(); ++i)
    for (std::size_t k = off[i]; k < off[i + 1]; ++k) {
      if (slot_[k] < 0)
        continue;
      const auto& st = sys.contacts.state(static_cast<std::size_t>(slot_[k]));
      if (st.age == 0)
        continue;
      const std::size_t j = nb[k];
      f(i, j, Vec<dim>(sys.cell.length.cwiseProduct(p.position[j] - p.position[i])), st);
    }
}

extern template class ContactForceLoop<2>;
extern template class ContactForceLoop<3>;

} // namespace granpack
