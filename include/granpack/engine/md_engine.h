#pragma once
// The distributed MD engine: one time step of grains + stress-controlled cell on the domain
// decomposition. The step reads like the algorithm (docs/ARCHITECTURE.md, "A time step"):
//   half-kick (grains, cell) -> drift -> rebuild (migrate, ghosts, Verlet list) or refresh
//   ghosts -> contact forces -> reverse communication of ghost forces -> half-kick ->
//   global stress and kinetic energy (one all-reduce) -> cell half-kick.
// Physics comes from the MPI-free kernels (contact law, force loop, integrator, cell
// control); communication from comm/. Every public member is collective on ctx.world.
#include <Eigen/Core>
#include <functional>
#include <vector>

#include "granpack/comm/halo.h"
#include "granpack/contact/contact_law.h"
#include "granpack/dynamics/cell_control.h"
#include "granpack/dynamics/contact_forces.h"
#include "granpack/dynamics/equilibrium.h"
#include "granpack/engine/run_context.h"
#include "granpack/engine/step_timers.h"
#include "granpack/neighbor/verlet_list.h"

namespace granpack {

template <int dim> struct MdSettings {
  double dt = 0;   ///< time step, s
  double skin = 0; ///< Verlet skin, m
  bool stress_control = false;
  CellControl<dim> cell; ///< used when stress_control
  /// Largest overlap h / min(R_i, R_j) accepted before the run stops with a diagnosis.
  double max_overlap = 0.1;
  /// Largest displacement of a grain in one step, as a fraction of the skin, before the run
  /// stops with a diagnosis (a grain jumping that far resolves no collision: blow-up).
  double max_step_displacement = 1.0;
  /// Load balancing ([numerics] load_balance): at a rebuild, the cut planes move to the
  /// quantiles of the grains when the largest rank's grain count exceeds this multiple of the
  /// mean (comm/rebalance.h). 0: the static grid.
  double load_balance_threshold = 0;
  /// How the halo's forward and reverse exchanges reach other ranks ([numerics] halo):
  /// messages, or a shared-memory window when every rank is on one node (comm/halo.h). The
  /// results are the same bit for bit; only the time differs.
  HaloTransport halo = HaloTransport::messages;
  /// When set (fix_rattlers), only the grains whose ids are in this sorted list move; the
  /// others are held at rest. Mobile grains also feel body_force(id) if it is set.
  const std::vector<GlobalId>* mobile = nullptr;
  std::function<Vec<dim>(GlobalId)> body_force;
  /// When set, only the pairs of grains (id_a < id_b) it accepts may interact: a frozen
  /// contact network ([AR] App. E tests without contact creation). Applied at every list build.
  std::function<bool(GlobalId, GlobalId)> pair_allowed;
};

/// The settings the deck's [numerics] fix for every MD stage: the Verlet skin, the overlap
/// limit of the blow-up check, load balancing and the halo's transport (the stage sets the
/// time step and the cell control).
template <int dim> MdSettings<dim> deck_md_settings(const RunContext<dim>& ctx) {
  MdSettings<dim> s;
  s.skin = ctx.deck->numerics.skin * ctx.deck->sample.diameter;
  s.max_overlap = ctx.deck->numerics.max_overlap;
  if (ctx.deck->numerics.load_balance)
    s.load_balance_threshold = ctx.deck->numerics.load_balance_threshold;
  s.halo = ctx.deck->numerics.halo == "shared_memory" ? HaloTransport::shared_memory
                                                      : HaloTransport::messages;
  return s;
}

/// Global observables after a step (identical on every rank).
template <int dim> struct MdObservables {
  Tensor<dim> stress = Tensor<dim>::Zero();         ///< eq. (8): contacts + kinetic, Pa
  Tensor<dim> stress_elastic = Tensor<dim>::Zero(); ///< elastic contact forces only, Pa
  double kinetic_energy = 0;                        ///< J (translational + rotational)
  std::int64_t contacts = 0;                        ///< interacting pairs
  double max_overlap = 0;                           ///< largest h / min(R_i, R_j)
  double max_step_displacement = 0;                 ///< largest |v| dt of the step, m
};

template <int dim> class MdEngine {
public:
  MdEngine(RunContext<dim>& ctx, const ContactLaw<dim>& law, const MdSettings<dim>& settings);
  /// Adds the engine's phase times to the stage's (RunContext::stage_timers).
  ~MdEngine() {
    ctx_.stage_timers.md += timers_;
    ctx_.stage_rebalances += rebalances_;
  }
  MdEngine(const MdEngine&) = delete;
  MdEngine& operator=(const MdEngine&) = delete;
  /// Advances one time step.
  void step();
  const MdObservables<dim>& observables() const { return obs_; }
  /// The equilibrium criteria values (dynamics/equilibrium.h), normalised by the scales;
  /// needs one extra pass over the contacts. Moments are measured only when with_moment.
  EquilibriumMeasure measure(const EquilibriumScales& scales, bool with_moment);
  /// Lists the force-carrying contacts (N^e > threshold) of this rank, by local index.
  template <class F> void for_each_contact(F&& f) const {
    loop_.for_each_contact(ctx_.system, list_, f);
  }
  const Halo<dim>& halo() const { return halo_; }
  const ContactLaw<dim>& law() const { return law_; }
  std::int64_t rebuilds() const { return rebuilds_; }
  /// How many rebuilds moved the cut planes (load balancing).
  std::int64_t rebalances() const { return rebalances_; }
  double dt() const { return settings_.dt; }
  /// Seconds spent in each phase of step() (and of the constructor) on this rank.
  const StepTimers& timers() const { return timers_; }
  MdSettings<dim>& settings() { return settings_; }

private:
  /// Migration, canonical (spatial) order of the owned grains, halo, Verlet list; with load
  /// balancing, new cut planes when the work is uneven (and the same again after them).
  void rebuild();
  /// The canonical order of the owned grains, the halo and the Verlet list.
  void build_halo_and_list(double cutoff);
  /// Per owned grain, the work of the current lists (2 + the pairs it belongs to).
  std::vector<std::int64_t> grain_work();
  /// Second half of a step: forces, sanity, half-kick, time. Also completes the step a
  /// checkpoint interrupted, on restart.
  void finish_step();
  /// Stops every rank with a diagnosis (grain, step, likely fix) on NaN/Inf or an excessive
  /// overlap. Collective; costs nothing unless something is wrong.
  void check_sanity();
  /// DIR/postmortem.h5: the bad state, for the user to inspect (collective, never throws).
  void write_postmortem();
  void forces_and_observables();
  /// Holds the non-mobile grains at rest and adds the body forces (settings_.mobile).
  void hold_and_push();
  /// Tallies the step just finished as dense or loose (by the contacts the step's all-reduce
  /// counted: no communication) with the phase time since the last tally.
  void tally_step();

  RunContext<dim>& ctx_;
  ContactLaw<dim> law_;
  MdSettings<dim> settings_;
  Halo<dim> halo_;
  VerletList<dim> list_;
  ContactForceLoop<dim> loop_;
  MdObservables<dim> obs_;
  StepTimers timers_;
  double tallied_seconds_ = 0; ///< timers_.total() at the last tally_step()
  std::int64_t n_grains_ = 0;  ///< over all ranks
  double max_radius_ = 0;
  std::int64_t rebuilds_ = 0, rebalances_ = 0;
};

extern template class MdEngine<2>;
extern template class MdEngine<3>;

} // namespace granpack
