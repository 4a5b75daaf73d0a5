// `granpack analyze`, pair section: g(r) and the gap-dependent coordination z(h) of [AR]
// sec. III C-D and IV C, for all grains (treatment I; II when the file follows fix_rattlers)
// and without the rattlers (III), with the fits of eq. (35). Each pair is counted once over
// all ranks: by the owned grain of smaller id (every owned grain sees all its neighbours
// within the ghost width).
#include <algorithm>
#include <cmath>

#include "granpack/analysis/pair_statistics.h"
#include "granpack/app/analysis_sections.h"
#include "granpack/comm/reduce.h"

namespace granpack {

namespace {

template <class Acc> void all_reduce(Acc& acc, MPI_Comm world) {
  global_sum_in_place(world, acc.sums());
}

nlohmann::json fit_json(const std::vector<double>& h, const std::vector<double>& z) {
  try {
    const PowerLawFit f = fit_gap_coordination(h, z);
    return {{"z0", f.z0},
            {"A", f.amplitude},
            {"beta", f.exponent},
            {"z0_error", f.z0_error},
            {"A_error", f.amplitude_error},
            {"beta_error", f.exponent_error},
            {"rms_residual", f.rms_residual},
            {"points", f.points}};
  } catch (const Error& e) {
    return {{"error", e.what()}};
  }
}

} // namespace

template <int dim> nlohmann::json analyze_pairs(const PackingView<dim>& v, const PairOptions& o) {
  const auto& p = v.particles();
  const double a = v.diameter;
  // z(h) needs gaps up to 0.5 a, i.e. centres up to R_i + R_j + 0.5 a <= 1.5 a (the view
  // guarantees that); g(r) goes as far as the ghost layer allows, at most r_max.
  const double r_max = std::min(o.r_max, v.ghost_width / a);
  const double reach = std::max(r_max * a, 1.5 * a);
  PairCorrelation<dim> g1(a, r_max, o.bin_width), g3(a, r_max, o.bin_width);
  const auto grid = GapCoordination::log_grid();
  GapCoordination z1(a, grid), z3(a, grid);
  for_each_neighbor(v, reach, [&](std::size_t i, std::size_t j, const Vec<dim>&, double r) {
    if (p.id[i] >= p.id[j])
      return;
    const bool backbone = !v.rattler(i) && !v.rattler(j);
    g1.add(r);
    z1.add(r - p.radius[i] - p.radius[j]);
    if (backbone) {
      g3.add(r);
      z3.add(r - p.radius[i] - p.radius[j]);
    }
  });
  for (auto* acc : {&g1, &g3})
    all_reduce(*acc, v.world);
  for (auto* acc : {&z1, &z3})
    all_reduce(*acc, v.world);
  const double n = double(v.n), n3 = n - double(v.backbone.metrics.rattlers);
  const double volume = v.system.cell.volume();
  const auto r1 = g1.finish(n, volume);
  const auto zh1 = z1.finish(n);
  nlohmann::json j;
  std::vector<double> r_mid(r1.r_lo.size());
  for (std::size_t k = 0; k < r_mid.size(); ++k)
    r_mid[k] = 0.5 * (r1.r_lo[k] + r1.r_hi[k]);
  j["g_r_range"] = r_max;
  j["g_r_range_requested"] = o.r_max;
  // A shorter range than requested is said, with why: half the cell is a property of the
  // packing; the sub-domain width (nearest-neighbour ghost exchange) one of the rank count.
  const double half_cell = 0.5 * v.system.cell.length.minCoeff() / a;
  j["g_r_range_limited_by"] = r_max >= o.r_max                  ? "request"
                              : r_max >= half_cell * (1 - 1e-6) ? "half the cell"
                                                                : "sub-domain width";
  j["g_r"] = {{"r_over_a", r_mid}, {"g_I", r1.g}, {"g_III", nullptr}};
  j["z_h"] = {{"h_over_a", grid}, {"z_I", zh1}, {"z_III", nullptr}};
  j["z_h_fit_I"] = fit_json(grid, zh1);
  j["z_h_fit_III"] = nullptr;
  // Treatment III (rattlers removed) needs a backbone: a gas or a loose, unjammed file has none.
  if (n3 >= 2) {
    const auto r3 = g3.finish(n3, volume);
    const auto zh3 = z3.finish(n3);
    j["g_r"]["g_III"] = r3.g;
    j["z_h"]["z_III"] = zh3;
    j["z_h_fit_III"] = fit_json(grid, zh3);
  }
  return j;
}

template nlohmann::json analyze_pairs<2>(const PackingView<2>&, const PairOptions&);
template nlohmann::json analyze_pairs<3>(const PackingView<3>&, const PairOptions&);

} // namespace granpack
