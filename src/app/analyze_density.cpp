// `granpack analyze`, density section (2D): [GRC] sec. V. The disks are gathered on rank 0,
// which rasterises chi on a mesh of spacing about `spacing` a (a/100 by default, as [GRC]),
// computes I(k) by FFT, fits eq. (28) and finds the holes; the results are broadcast.
#include <cmath>
#include <numbers>

#include "granpack/analysis/density_correlation.h"
#include "granpack/app/analysis_sections.h"
#include "granpack/comm/gather.h"

namespace granpack {

nlohmann::json analyze_density(const PackingView<2>& v, const DensityOptions& o) {
  const auto grains = gather_particles(v.particles(), v.world);
  int rank = 0;
  MPI_Comm_rank(v.world, &rank);
  std::string text;
  if (rank == 0) {
    const Vec<2> L = v.system.cell.length;
    const double a = v.diameter;
    double spacing = o.spacing * a;
    // Keep the mesh within max_nodes (the FFT needs about 24 bytes per node).
    const double nodes = L[0] * L[1] / (spacing * spacing);
    if (nodes > o.max_nodes) spacing *= std::sqrt(nodes / o.max_nodes);
    const int nx = int(std::ceil(L[0] / spacing)), ny = int(std::ceil(L[1] / spacing));
    std::vector<Disk> disks;
    for (const auto& g : grains) disks.push_back({v.system.cell.to_real(g.position), g.radius});
    const auto chi = rasterize_disks(disks, L, nx, ny);
    const double k_max = 2 * std::numbers::pi / (o.k_max_wavelength * a);
    const auto c = scattering_function(chi, L, nx, ny, 2 * std::numbers::pi / (4 * spacing), o.bins);
    const double k_lo = 2 * std::numbers::pi / std::max(L[0], L[1]);
    const FractalFit f = fit_fractal_blob(c, k_lo, k_max, v.phi);
    const HoleStatistics h = hole_statistics(chi, L, nx, ny);
    double solid = 0;
    for (auto x : chi) solid += x;
    std::vector<double> k_a(c.k.size()), I_a(c.k.size()), e_a(c.k.size());
    for (std::size_t b = 0; b < c.k.size(); ++b)
      k_a[b] = c.k[b] * a, I_a[b] = c.I[b] / (a * a), e_a[b] = c.I_error[b] / (a * a);
    std::vector<double> radii_a(h.radii.size());
    for (std::size_t k = 0; k < h.radii.size(); ++k) radii_a[k] = h.radii[k] / a;
    nlohmann::json j;
    j["mesh"] = {{"nx", nx}, {"ny", ny}, {"spacing_over_a", L[0] / nx / a},
                 {"phi_of_mesh", solid / double(chi.size())}};
    j["I_k"] = {{"k_times_a", k_a}, {"I_over_a2", I_a}, {"I_error_over_a2", e_a}, {"count", c.count}};
    j["fit_eq28"] = {{"d_F", f.d_f}, {"d_F_error", f.d_f_error}, {"xi_over_a", f.xi / a},
                     {"xi_error_over_a", f.xi_error / a}, {"constant_over_a2", f.constant / (a * a)},
                     {"amplitude", f.amplitude}, {"l_over_a", f.length_l / a},
                     {"rms_log_residual", f.rms_log_residual}, {"points", f.points},
                     {"k_range_times_a", {k_lo * a, k_max * a}}, {"converged", f.converged}};
    // The fit means something only with a blob size inside the fitted range and a determined
    // d_F; dense or small samples (no fractal regime) fail this and say so.
    j["fit_eq28"]["fractal_regime"] = f.converged && f.points >= 6 && f.xi > 1 / k_max &&
                                      f.xi < 0.5 * std::min(L[0], L[1]) && f.d_f > 1 && f.d_f < 2.1 &&
                                      f.d_f_error < 0.2;
    j["holes"] = {{"count", h.holes}, {"wrapping", h.wrapping_holes},
                  {"R_w_over_a", h.weighted_mean_radius / a}, {"largest_R_over_a", h.largest_radius / a},
                  {"radii_over_a", radii_a}, {"nodes", h.nodes}};
    text = j.dump();
  }
  int size = int(text.size());
  MPI_Bcast(&size, 1, MPI_INT, 0, v.world);
  text.resize(std::size_t(size));
  MPI_Bcast(text.data(), size, MPI_CHAR, 0, v.world);
  return nlohmann::json::parse(text);
}

}  // namespace granpack
