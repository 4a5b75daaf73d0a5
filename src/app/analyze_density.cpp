// `granpack analyze`, density section (2D): [GRC] sec. V. The disks are gathered on rank 0,
// which rasterises chi on a mesh of spacing about `spacing` a (a/100 by default, as [GRC]),
// computes I(k) and C(r) by FFT, fits eq. (28) to I(k) and eq. (27) to C(r), and finds the
// holes; the results are broadcast. Lengths are reported in units of a.
#include <cmath>
#include <numbers>

#include "granpack/analysis/density_correlation.h"
#include "granpack/app/analysis_sections.h"
#include "granpack/app/density_fit_json.h"
#include "granpack/comm/broadcast.h"
#include "granpack/comm/communicator.h"
#include "granpack/comm/gather.h"

namespace granpack {

nlohmann::json analyze_density(const PackingView<2>& v, const DensityOptions& o) {
  const auto grains = gather_particles(v.particles(), v.world);
  const int rank = rank_of(v.world);
  std::string text;
  if (rank == 0) {
    const Vec<2> L = v.system.cell.length;
    const double a = v.diameter;
    double spacing = o.spacing * a;
    // Keep the mesh within max_nodes (the FFT needs about 24 bytes per node).
    const double nodes = L[0] * L[1] / (spacing * spacing);
    if (nodes > o.max_nodes)
      spacing *= std::sqrt(nodes / o.max_nodes);
    // At most the requested spacing, with node counts the FFT is fast on.
    const int nx = fft_friendly_size(int(std::ceil(L[0] / spacing))),
              ny = fft_friendly_size(int(std::ceil(L[1] / spacing)));
    std::vector<Disk> disks;
    for (const auto& g : grains)
      disks.push_back({v.system.cell.to_real(g.position), g.radius});
    const auto chi = rasterize_disks(disks, L, nx, ny);
    const double k_max = 2 * std::numbers::pi / (o.k_max_wavelength * a);
    const double l_cell = std::min(L[0], L[1]);
    const DensitySpectra sp = density_spectra(chi, L, nx, ny, 2 * std::numbers::pi / (4 * spacing),
                                              o.bins, 0.5 * l_cell, o.r_bin * a);
    const ScatteringCurve& c = sp.scattering;
    const double k_lo = 2 * std::numbers::pi / std::max(L[0], L[1]);
    // A xi beyond the cell is no cut-off the sample can show: undetermined.
    const double xi_max = std::max(L[0], L[1]);
    const FractalFit f = fit_fractal_blob(c, k_lo, k_max, v.phi, xi_max);
    const FractalFit fr =
        fit_fractal_real_space(sp.correlation, o.r_min * a, 0.5 * l_cell, v.phi, xi_max);
    const HoleStatistics h = hole_statistics(chi, L, nx, ny);
    double solid = 0;
    for (auto x : chi)
      solid += x;
    std::vector<double> k_a(c.k.size()), I_a(c.k.size()), e_a(c.k.size());
    for (std::size_t b = 0; b < c.k.size(); ++b)
      k_a[b] = c.k[b] * a, I_a[b] = c.I[b] / (a * a), e_a[b] = c.I_error[b] / (a * a);
    std::vector<double> r_a(sp.correlation.r.size());
    for (std::size_t b = 0; b < r_a.size(); ++b)
      r_a[b] = sp.correlation.r[b] / a;
    std::vector<double> radii_a(h.radii.size());
    for (std::size_t k = 0; k < h.radii.size(); ++k)
      radii_a[k] = h.radii[k] / a;
    nlohmann::json j;
    j["mesh"] = {{"nx", nx},
                 {"ny", ny},
                 {"spacing_over_a", L[0] / nx / a},
                 {"cell_over_a", {L[0] / a, L[1] / a}},
                 {"phi_of_mesh", solid / double(chi.size())}};
    j["I_k"] = {
        {"k_times_a", k_a}, {"I_over_a2", I_a}, {"I_error_over_a2", e_a}, {"count", c.count}};
    j["C_r"] = {
        {"r_over_a", r_a}, {"C_minus_phi2", sp.correlation.C}, {"count", sp.correlation.count}};
    j["fit_eq28"] = fractal_fit_json(f, a, l_cell);
    j["fit_eq28"]["constant_over_a2"] =
        f.determined ? nlohmann::json(f.constant / (a * a)) : nlohmann::json(nullptr);
    j["fit_eq28"]["k_range_times_a"] = {k_lo * a, k_max * a};
    j["fit_eq28"]["k_used_times_a"] = {f.lo * a, f.hi * a};
    j["fit_eq27_real_space"] = fractal_fit_json(fr, a, l_cell);
    j["fit_eq27_real_space"]["r_range_over_a"] = {o.r_min, 0.5 * l_cell / a};
    j["fit_eq27_real_space"]["r_used_over_a"] = {fr.lo / a, fr.hi / a};
    j["holes"] = {{"count", h.holes},
                  {"wrapping", h.wrapping_holes},
                  {"R_w_over_a", h.weighted_mean_radius / a},
                  {"largest_R_over_a", h.largest_radius / a},
                  {"radii_over_a", radii_a},
                  {"nodes", h.nodes}};
    text = j.dump();
  }
  broadcast_string(v.world, text);
  return nlohmann::json::parse(text);
}

} // namespace granpack
