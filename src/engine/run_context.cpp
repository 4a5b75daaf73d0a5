#include "granpack/engine/run_context.h"

#include <numbers>

#include "granpack/comm/reduce.h"

namespace granpack {

template <int dim> double RunContext<dim>::solid_fraction() const {
  double local = 0;
  const auto& p = system.particles;
  for (std::size_t i = 0; i < p.n_owned(); ++i) {
    double r = p.radius[i];
    local += dim == 3 ? 4.0 / 3.0 * std::numbers::pi * r * r * r : std::numbers::pi * r * r;
  }
  return global_sum(world, local) / system.cell.volume();
}

template struct RunContext<2>;
template struct RunContext<3>;

} // namespace granpack
