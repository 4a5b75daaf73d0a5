#include "granpack/prep/md_engine.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "granpack/comm/collective_error.h"
#include "granpack/comm/migration.h"
#include "granpack/comm/reduce.h"
#include "granpack/core/error.h"
#include "granpack/dynamics/integrator.h"

namespace granpack {

template <int dim>
MdEngine<dim>::MdEngine(RunContext<dim>& ctx, const ContactLaw<dim>& law,
                        const MdSettings<dim>& settings)
    : ctx_(ctx), law_(law), settings_(settings) {
  GRANPACK_CHECK(ctx.decomposition, "the MD engine needs a sample (a lattice or random stage)");
  GRANPACK_CHECK(settings.dt > 0, "time step must be positive");
  double r = 0;
  for (std::size_t i = 0; i < ctx.system.particles.n_owned(); ++i)
    r = std::max(r, ctx.system.particles.radius[i]);
  max_radius_ = global_max(ctx.world, r);
  rebuild();
  forces_and_observables();
}

template <int dim> void MdEngine<dim>::rebuild() {
  auto& sys = ctx_.system;
  {
    ScopedPhase t(timers_.comm);
    sys.particles.clear_ghosts();
    migrate(sys, *ctx_.decomposition);
    // Ghost layer: every grain that can come within reach of ours before the next rebuild.
    const double cutoff = 2 * max_radius_ + law_.interaction_range() + settings_.skin;
    halo_.borders(sys.particles, *ctx_.decomposition, Vec<dim>::Constant(cutoff).cwiseQuotient(sys.cell.length));
  }
  ScopedPhase t(timers_.neighbor);
  collectively(ctx_.world, [&] {
    list_.build(sys.particles, sys.cell, NeighborParams{settings_.skin, law_.interaction_range()});
  });
  loop_.bind(sys.particles, list_, sys.contacts);
  ++rebuilds_;
}

template <int dim> void MdEngine<dim>::forces_and_observables() {
  auto& sys = ctx_.system;
  ForceSums<dim> sums;
  {
    ScopedPhase t(timers_.forces);
    sums = loop_.compute(sys, list_, law_, settings_.dt);
  }
  {
    ScopedPhase t(timers_.comm);
    halo_.reverse(sys.particles, *ctx_.decomposition);
  }
  if (settings_.mobile) hold_and_push();

  // One all-reduce for every global sum of the step.
  constexpr int nt = dim * dim;
  double local[2 * nt + 2], global[2 * nt + 2];
  Tensor<dim> kinetic = Tensor<dim>::Zero();
  const auto& p = sys.particles;
  double ek = 0;
  for (std::size_t i = 0; i < p.n_owned(); ++i) {
    kinetic.noalias() += p.mass[i] * p.velocity[i] * p.velocity[i].transpose();
    ek += 0.5 * p.inertia[i] * p.angular_velocity[i].squaredNorm();
  }
  ek += 0.5 * kinetic.trace();
  Eigen::Map<Tensor<dim>> total_part(local), elastic_part(local + nt);
  total_part = sums.virial + kinetic;
  elastic_part = sums.virial_elastic;
  local[2 * nt] = ek;
  local[2 * nt + 1] = static_cast<double>(sums.interacting);
  ScopedPhase t(timers_.comm);
  MPI_Allreduce(local, global, 2 * nt + 2, MPI_DOUBLE, MPI_SUM, ctx_.world);
  const double volume = sys.cell.volume();
  obs_.stress = Eigen::Map<Tensor<dim>>(global) / volume;
  obs_.stress_elastic = Eigen::Map<Tensor<dim>>(global + nt) / volume;
  obs_.kinetic_energy = global[2 * nt];
  obs_.contacts = static_cast<std::int64_t>(global[2 * nt + 1]);
  obs_.max_overlap = global_max(ctx_.world, sums.max_overlap);
}

template <int dim> void MdEngine<dim>::hold_and_push() {
  auto& p = ctx_.system.particles;
  const auto& mobile = *settings_.mobile;
  for (std::size_t i = 0; i < p.n_owned(); ++i) {
    if (std::binary_search(mobile.begin(), mobile.end(), p.id[i])) {
      if (settings_.body_force) p.force[i] += settings_.body_force(p.id[i]);
    } else {
      p.force[i].setZero();
      p.torque[i].setZero();
      p.velocity[i].setZero();
      p.angular_velocity[i].setZero();
    }
  }
}

template <int dim> void MdEngine<dim>::step() {
  auto& sys = ctx_.system;
  auto& p = sys.particles;
  const double dt = settings_.dt;
  {
    ScopedPhase t(timers_.integrate);
    kick(p, 0.5 * dt);
    if (settings_.stress_control) settings_.cell.kick(sys.cell, obs_.stress.diagonal(), 0.5 * dt);
    drift(p, sys.cell, dt);
    if (settings_.stress_control) CellControl<dim>::drift(sys.cell, dt);
  }

  int local = 0, any = 0;
  {
    ScopedPhase t(timers_.neighbor);
    local = list_.needs_rebuild(p, sys.cell) ? 1 : 0;
  }
  {
    ScopedPhase t(timers_.comm);
    MPI_Allreduce(&local, &any, 1, MPI_INT, MPI_MAX, ctx_.world);
  }
  if (any) {
    rebuild();
  } else {
    ScopedPhase t(timers_.comm);
    halo_.forward(p, *ctx_.decomposition);
  }

  forces_and_observables();
  check_sanity();
  ScopedPhase t(timers_.integrate);
  kick(p, 0.5 * dt);
  if (settings_.stress_control) settings_.cell.kick(sys.cell, obs_.stress.diagonal(), 0.5 * dt);
  sys.time += dt;
  ++sys.step;
}

template <int dim> void MdEngine<dim>::check_sanity() {
  // Global values first (identical on every rank, so every rank decides alike); the search
  // for the culprit grain runs only when something is wrong.
  const bool finite = obs_.stress.allFinite() && std::isfinite(obs_.kinetic_energy);
  const bool overlap_ok = obs_.max_overlap <= settings_.max_overlap;
  if (finite && overlap_ok) return;
  CollectiveError err;
  const auto& p = ctx_.system.particles;
  for (std::size_t i = 0; i < p.n_owned(); ++i) {
    if (!p.position[i].allFinite() || !p.velocity[i].allFinite() || !p.force[i].allFinite()) {
      err.record("step " + std::to_string(ctx_.system.step) + ": grain " + std::to_string(p.id[i]) +
                 " has a non-finite position, velocity or force (likely fix: a smaller "
                 "[numerics] time_step_fraction)");
      break;
    }
  }
  if (!err.has_local() && !finite)
    err.record("step " + std::to_string(ctx_.system.step) +
               ": the stress or kinetic energy is not finite (likely fix: a smaller "
               "[numerics] time_step_fraction)");
  if (!err.has_local() && !overlap_ok) {
    std::ostringstream os;
    os << "step " << ctx_.system.step << ": a contact overlap reached " << obs_.max_overlap
       << " of the grain radius (limit " << settings_.max_overlap
       << "): the contacts are too soft for the pressure or the time step too large (likely "
          "fix: a smaller [numerics] time_step_fraction, stiffer material or a cap "
          "inertia_max on the compression)";
    err.record(os.str());
  }
  err.raise_if_any(ctx_.world);
}

template <int dim>
EquilibriumMeasure MdEngine<dim>::measure(double force_scale, double stress_scale,
                                          double energy_scale) {
  auto& sys = ctx_.system;
  std::vector<Vec<dim>> fel;
  loop_.elastic_forces(sys, list_, fel);
  std::vector<double> comp(fel.size());
  double fmax = 0;
  std::vector<double> norm2(sys.particles.n_owned(), 0.0);
  for (int a = 0; a < dim; ++a) {
    for (std::size_t i = 0; i < fel.size(); ++i) comp[i] = fel[i][a];
    halo_.reverse_values(comp, *ctx_.decomposition);
    for (std::size_t i = 0; i < norm2.size(); ++i) norm2[i] += comp[i] * comp[i];
  }
  for (double f2 : norm2) fmax = std::max(fmax, f2);
  EquilibriumMeasure m;
  m.force = std::sqrt(global_max(ctx_.world, fmax)) / force_scale;
  double err = 0;
  for (int a = 0; a < dim; ++a)
    if (!settings_.cell.fixed[a])
      err = std::max(err, std::abs(obs_.stress_elastic(a, a) - settings_.cell.target[a]));
  m.stress = err / stress_scale;
  // Kinetic energy, leaving out the spin of grains without any contact: a caged rattler
  // spinning freely keeps its rotational energy forever (only normal damping and friction
  // dissipate, both need a contact), yet it has no mechanical effect on the packing.
  const auto& p = sys.particles;
  std::vector<double> touching(p.size(), 0.0);
  loop_.for_each_contact(sys, list_, [&](std::size_t i, std::size_t j, const Vec<dim>&,
                                         const ContactState<dim>&) {
    touching[i] += 1;
    touching[j] += 1;
  });
  halo_.reverse_values(touching, *ctx_.decomposition);
  double ek = 0;
  for (std::size_t i = 0; i < p.n_owned(); ++i) {
    ek += 0.5 * p.mass[i] * p.velocity[i].squaredNorm();
    if (touching[i] > 0) ek += 0.5 * p.inertia[i] * p.angular_velocity[i].squaredNorm();
  }
  const auto n = global_sum(ctx_.world, static_cast<std::int64_t>(p.n_owned()));
  m.kinetic = global_sum(ctx_.world, ek) / static_cast<double>(n) / energy_scale;
  return m;
}

template class MdEngine<2>;
template class MdEngine<3>;

}  // namespace granpack
