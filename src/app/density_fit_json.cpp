#include "granpack/app/density_fit_json.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace granpack {

nlohmann::json fractal_fit_json(const FractalFit& f, double a, double l_cell) {
  auto num = [&](double x) { return f.determined ? nlohmann::json(x) : nlohmann::json(nullptr); };
  const std::string failure = fractal_regime_failure(f, a, l_cell);
  // Phi l^(2-d_F) has the dimension of a length to the power 2 - d_F: in units of a, Phi
  // (l/a)^(2-d_F).
  return {{"d_F", num(f.d_f)},
          {"d_F_error", num(f.d_f_error)},
          {"xi_over_a", num(f.xi / a)},
          {"xi_error_over_a", num(f.xi_error / a)},
          {"amplitude_over_a_pow_2_minus_dF", num(f.amplitude / std::pow(a, 2 - f.d_f))},
          {"l_over_a", num(f.length_l / a)},
          {"rms_log_residual", f.rms_log_residual},
          {"points", f.points},
          {"converged", f.converged},
          {"determined", f.determined},
          {"reason", f.determined ? nlohmann::json(nullptr) : nlohmann::json(f.reason)},
          {"fractal_regime", failure.empty()},
          {"regime_failure", failure.empty() ? nlohmann::json(nullptr) : nlohmann::json(failure)}};
}

namespace {

/// The cell sides / a of an analysis: `cell_over_a` when the file has it, else the mesh's x
/// side for both (files written before it was recorded; their cells are square).
std::pair<double, double> cell_sides(const nlohmann::json& mesh) {
  if (mesh.contains("cell_over_a"))
    return {mesh["cell_over_a"][0].get<double>(), mesh["cell_over_a"][1].get<double>()};
  const double l = mesh.at("nx").get<double>() * mesh.at("spacing_over_a").get<double>();
  return {l, l};
}

} // namespace

nlohmann::json pooled_density_json(const std::vector<nlohmann::json>& density_sections) {
  std::vector<ScatteringCurve> curves;
  double phi = 0, k_lo = std::numeric_limits<double>::infinity(), k_hi = k_lo;
  double l_min = k_lo, l_max = 0;
  for (const auto& d : density_sections) {
    if (!d.is_object() || !d.contains("I_k") || !d.contains("fit_eq28") || !d.contains("mesh"))
      continue;
    const auto& ik = d["I_k"];
    ScatteringCurve c;
    c.k = ik.at("k_times_a").get<std::vector<double>>();
    c.I = ik.at("I_over_a2").get<std::vector<double>>();
    c.I_error = ik.at("I_error_over_a2").get<std::vector<double>>();
    c.count = ik.at("count").get<std::vector<double>>();
    curves.push_back(std::move(c));
    phi += d["mesh"].at("phi_of_mesh").get<double>();
    // The common window: from the largest cell's smallest k (every sample's bins below it
    // are empty) to the smallest of the samples' upper ends.
    const auto& range = d["fit_eq28"].at("k_range_times_a");
    k_lo = std::min(k_lo, range[0].get<double>());
    k_hi = std::min(k_hi, range[1].get<double>());
    const auto [l1, l2] = cell_sides(d["mesh"]);
    l_min = std::min({l_min, l1, l2});
    l_max = std::max({l_max, l1, l2});
  }
  nlohmann::json j = {{"K", curves.size()}};
  if (curves.empty())
    return j;
  phi /= double(curves.size());
  const ScatteringCurve pooled = pooled_scattering(curves);
  // Units of a throughout (a = 1); a xi beyond the largest cell is no cut-off it can show.
  const FractalFit f = fit_fractal_blob(pooled, k_lo, k_hi, phi, l_max);
  j["phi_of_mesh"] = phi;
  j["I_k"] = {{"k_times_a", pooled.k},
              {"I_over_a2", pooled.I},
              {"I_error_over_a2", pooled.I_error},
              {"count", pooled.count}};
  j["fit_eq28"] = fractal_fit_json(f, 1.0, l_min);
  j["fit_eq28"]["constant_over_a2"] =
      f.determined ? nlohmann::json(f.constant) : nlohmann::json(nullptr);
  j["fit_eq28"]["k_range_times_a"] = {k_lo, k_hi};
  j["fit_eq28"]["k_used_times_a"] = {f.lo, f.hi};
  return j;
}

} // namespace granpack
