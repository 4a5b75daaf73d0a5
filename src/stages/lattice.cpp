// `lattice` stage: grains on the sites of a perfect crystal at solid fraction phi, at rest.
// 3D: face-centred cubic, 4 grains per cubic unit cell of side A, phi = 4 (pi/6) a^3 / A^3.
// 2D: triangular, 2 grains per rectangular unit cell A x A sqrt(3), phi = pi a^2 / (2 sqrt(3) A^2).
// Every rank walks all sites in the same order (ids are the site numbers) and keeps the ones
// in its sub-box, so the sample is identical whatever the rank count.
#include <cmath>
#include <numbers>

#include "granpack/core/error.h"
#include "granpack/stages/stages.h"

namespace granpack {

template <int dim> StageReport run_stage(RunContext<dim>& ctx, const LatticeStage& p) {
  const double a = ctx.deck->sample.diameter;
  const double pi = std::numbers::pi;
  GRANPACK_CHECK(ctx.system.particles.size() == 0,
                 "stage " << ctx.stage_index << " (lattice) needs an empty sample, but "
                          << ctx.system.particles.size() << " grains exist already");

  std::vector<Vec<dim>> basis;
  Vec<dim> unit; // unit cell edge lengths
  if constexpr (dim == 3) {
    double A = a * std::cbrt(4.0 * pi / (6.0 * p.phi));
    unit = Vec<3>(A, A, A);
    basis = {Vec<3>(0, 0, 0), Vec<3>(0.5, 0.5, 0), Vec<3>(0.5, 0, 0.5), Vec<3>(0, 0.5, 0.5)};
  } else {
    double A = a * std::sqrt(pi / (2.0 * std::sqrt(3.0) * p.phi));
    unit = Vec<2>(A, A * std::sqrt(3.0));
    basis = {Vec<2>(0, 0), Vec<2>(0.5, 0.5)};
  }
  Vec<dim> ncell;
  for (int k = 0; k < dim; ++k)
    ncell[k] = double(p.cells[k]);
  ctx.system.cell.length = unit.cwiseProduct(ncell);
  ctx.system.cell.rate.setZero();
  ctx.decomposition = std::make_unique<Decomposition<dim>>(ctx.world, ctx.system.cell.length);

  const double mass = HomogeneousGrain<dim>::mass(ctx.deck->material.density, a);
  const double inertia = HomogeneousGrain<dim>::inertia(mass, a);
  std::int64_t total = 1;
  for (auto c : p.cells)
    total *= c;
  GlobalId id = 0;
  for (std::int64_t flat = 0; flat < total; ++flat) {
    Vec<dim> c; // unit cell indices, last axis fastest
    std::int64_t rest = flat;
    for (int k = dim - 1; k >= 0; --k) {
      c[k] = double(rest % p.cells[k]);
      rest /= p.cells[k];
    }
    for (const auto& b : basis) {
      // Offset by a quarter cell so that no site sits exactly on a sub-box boundary.
      Vec<dim> s = (c + b + Vec<dim>::Constant(0.25)).cwiseQuotient(ncell);
      s = Cell<dim>::wrap(s);
      if (ctx.decomposition->owns(s)) {
        Particle<dim> q;
        q.id = id;
        q.radius = 0.5 * a;
        q.mass = mass;
        q.inertia = inertia;
        q.position = s;
        ctx.system.particles.add_owned(q);
      }
      ++id;
    }
  }

  return StageReport{};
}

template StageReport run_stage<2>(RunContext<2>&, const LatticeStage&);
template StageReport run_stage<3>(RunContext<3>&, const LatticeStage&);

} // namespace granpack
