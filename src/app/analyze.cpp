#include "granpack/app/analyze.h"

#include <cmath>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "granpack/app/analysis_sections.h"
#include "granpack/comm/communicator.h"
#include "granpack/io/hdf5_store.h"
#include "granpack/io/json_hdf5.h"
#include "granpack/io/report.h"

namespace granpack {

namespace {

template <int dim>
nlohmann::json analyze(MPI_Comm world, const AnalyzeOptions& opt, const FileMeta& meta) {
  const double reach = std::max(opt.pairs.r_max, 1.5); // z(h) to 0.5 a, bonds to 1.4 a
  const PackingView<dim> v = load_packing<dim>(world, opt.file, meta, opt.threshold, reach);
  nlohmann::json j = packing_summary(v, opt.file);
  j["carrying_threshold"] = opt.threshold; // --threshold: force_threshold in units of a^2 P
  j.update(analyze_network(v));
  j.update(analyze_pairs(v, opt.pairs));
  j["motifs"] = analyze_motifs(v);
  j["interactions"] = analyze_interactions(v);
  if constexpr (dim == 2)
    if (opt.density.enabled)
      j["density"] = analyze_density(v, opt.density);
  if constexpr (dim == 3)
    j["order"] = analyze_order(v);
  if constexpr (dim == 3)
    for (const char* k : {"Q4_local_mean", "Q6_local_mean", "Q6_global", "crystalline_fraction"})
      j[k] = j["order"][k];
  return j;
}

// Takes a copy: its non-const operator[] reads a key an unusual file's analysis left out
// as null ("-"), where the const one is undefined behaviour.
std::string table(nlohmann::json j) {
  std::string out;
  char buf[160];
  auto row = [&](const char* name, const std::string& value) {
    std::snprintf(buf, sizeof buf, "  %-26s %s\n", name, value.c_str());
    out += buf;
  };
  auto num = [](const nlohmann::json& v) {
    if (!v.is_number())
      return std::string("-");
    char b[32];
    std::snprintf(b, sizeof b, "%.6g", v.get<double>());
    return std::string(b);
  };
  out += "granpack analyze: " + j["file"].get<std::string>() + "\n";
  row("dimension, n",
      std::to_string(j["dimension"].get<int>()) + ", " + std::to_string(j["n"].get<long long>()));
  row("friction mu", j["friction"].dump());
  row("solid fraction Phi", num(j["phi"]));
  row("pressure (elastic) / Pa", num(j["pressure"]));
  row("force threshold / N", num(j["force_threshold"]));
  row("contacts: all / carrying",
      std::to_string(j["contacts_in_file"].get<long long>()) + " / " +
          std::to_string(j["force_carrying_contacts"].get<long long>()));
  row("rattler fraction x0", num(j["x0"]));
  row("coordination z", num(j["z"]));
  row("backbone coordination z*", num(j["z_star"]));
  std::string xs;
  for (auto& [k, v] : j["x_i"].items())
    xs += "x" + k + "=" + num(v) + " ";
  row("fractions x_i (backbone)", xs);
  row("<N> / N", num(j["mean_normal_force"]));
  row("Z(5/3), Z(2)", num(j["Z_5_3"]) + ", " + num(j["Z_2"]));
  if (j.contains("pressure_eq22") && !j["pressure_eq22"].is_null())
    row("eq. (22) z Phi <N>/(pi a^2)",
        num(j["pressure_eq22"]) + " Pa (relative error " + num(j["eq22_relative_error"]) + ")");
  if (j.contains("X1"))
    row("X1, M1, M2 (table VI)", num(j["X1"]) + ", " + num(j["M1"]) + ", " + num(j["M2"]));
  row("x2, H/N_f (eq. 37)", num(j["x2"]) + ", " + num(j["H_over_Nf"]));
  if (j.contains("delta_phi"))
    row("kappa, Delta Phi, Phi0 (28)",
        num(j["kappa"]) + ", " + num(j["delta_phi"]) + ", " + num(j["phi0"]));
  for (const char* t : {"I", "III"}) {
    auto& f = j[std::string("z_h_fit_") + t];
    if (f.contains("z0"))
      row((std::string("z(h) fit (35), ") + t + ": z0 A beta").c_str(),
          num(f["z0"]) + ", " + num(f["A"]) + ", " + num(f["beta"]));
  }
  if (j.contains("motifs"))
    row("triangles, tetrahedra/grain",
        num(j["motifs"]["triangles_per_grain"]) + ", " + num(j["motifs"]["tetrahedra_per_grain"]) +
            " (in a tetrahedron: " + num(j["motifs"]["fraction_in_tetrahedron"]) + ")");
  if (j.contains("interactions") && j["interactions"].contains("force_scale")) {
    auto& c = j["interactions"];
    row("interactions: z, z+ z- z0", num(c["z"]) + ", " + num(c["z_plus"]) + " " +
                                         num(c["z_minus"]) + " " + num(c["z_zero"]) + " (distant " +
                                         num(c["distant"]) + ")");
    row("Rumpf <N> / eq. (17)", num(c["rumpf"]["mean_normal_force"]) + " / " +
                                    num(c["rumpf"]["predicted_eq17"]) + " N (relative error " +
                                    num(c["rumpf"]["relative_error"]) + ")");
    row(("F_perc / " + c["force_scale_is"].get<std::string>()).c_str(),
        num(c["F_perc_over_Fs"]) + " (all directions " + num(c["F_perc_all_directions_over_Fs"]) +
            ")");
    row("vanishing, |N| > F_s/10",
        num(c["fraction_vanishing"]) + ", " + num(c["fraction_above_tenth"]));
    auto& m = c["force_means"];
    row("<|N|>/F_s: +, - (table VI)", num(m["repulsive"]["mean_abs_N_over_Fs"]) + ", " +
                                          num(m["attractive"]["mean_abs_N_over_Fs"]) + " (rms " +
                                          num(m["repulsive"]["rms_N_over_Fs"]) + ", " +
                                          num(m["attractive"]["rms_N_over_Fs"]) + ")");
    std::string xk;
    for (auto& [k, x] : c["x_k"].items())
      xk += "x" + k + "=" + num(x) + " ";
    row("x_k, all interactions", xk);
  }
  if (j.contains("density")) {
    auto& d = j["density"];
    for (const char* fit : {"fit_eq28", "fit_eq27_real_space"}) {
      auto& f = d[fit];
      row(fit == std::string("fit_eq28") ? "d_F, xi/a (eq. 28, I(k))" : "d_F, xi/a (eq. 27, C(r))",
          f["determined"].get<bool>()
              ? num(f["d_F"]) + " +- " + num(f["d_F_error"]) + ", " + num(f["xi_over_a"]) + " +- " +
                    num(f["xi_error_over_a"]) +
                    (f["fractal_regime"].get<bool>() ? "" : " (no fractal regime)")
              : "undetermined: " + f["reason"].get<std::string>());
    }
    row("holes, <R>_w/a (eq. 30)", std::to_string(d["holes"]["count"].get<long long>()) + " (" +
                                       std::to_string(d["holes"]["wrapping"].get<long long>()) +
                                       " wrapping), " + num(d["holes"]["R_w_over_a"]));
  }
  if (j.contains("g_r_range_limited_by") && j["g_r_range_limited_by"] != "request") {
    const bool ranks = j["g_r_range_limited_by"] == "sub-domain width";
    row("g(r) range / a", num(j["g_r_range"]) + " (" + num(j["g_r_range_requested"]) +
                              " requested; limited by " +
                              j["g_r_range_limited_by"].get<std::string>() +
                              (ranks ? ": run on fewer ranks for the full range)" : ")"));
  }
  if (j.contains("order")) {
    for (const char* dc : {"1.35", "1.40"}) {
      auto& o = j["order"][dc];
      row((std::string("order d_c=") + dc + "a: Z Z_cr Q6 Q6loc").c_str(),
          num(o["Z"]) + ", " + num(o["Z_cr"]) + ", " + num(o["Q6_global"]) + ", " +
              num(o["Q6_local_mean"]));
      row((std::string("  x_cr, <n_cr>")).c_str(),
          num(o["crystalline_fraction"]) + ", " + num(o["cluster_mass_average"]));
    }
  }
  return out;
}

} // namespace

std::string analyze_file(MPI_Comm world, const AnalyzeOptions& options) {
  const FileMeta meta = read_file_meta(world, options.file);
  nlohmann::json j =
      meta.dimension == 3 ? analyze<3>(world, options, meta) : analyze<2>(world, options, meta);
  const int rank = rank_of(world);
  if (rank == 0) {
    if (options.print_table)
      std::cout << table(j);
    if (options.json)
      write_text_atomically(*options.json, j.dump(2) + "\n");
    if (options.hdf5)
      write_json_as_hdf5(*options.hdf5, j);
  }
  return j.dump();
}

} // namespace granpack
