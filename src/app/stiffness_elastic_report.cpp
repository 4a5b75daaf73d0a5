#include "granpack/app/stiffness_elastic_report.h"

#include <cmath>
#include <cstdio>

namespace granpack {

namespace {

template <int dim> nlohmann::json rows_of(const VoigtMatrix<dim>& m) {
  nlohmann::json rows = nlohmann::json::array();
  for (int i = 0; i < voigt_size<dim>; ++i) {
    std::vector<double> row(voigt_size<dim>);
    for (int j = 0; j < voigt_size<dim>; ++j)
      row[j] = m(i, j);
    rows.push_back(row);
  }
  return rows;
}

/// NaN (Reuss of an indefinite tensor) as null.
nlohmann::json number(double x) {
  return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json();
}

template <int dim> nlohmann::json moduli_of(const ElasticSummary<dim>& s) {
  return {{"bulk_voigt", number(s.bulk_voigt)},      {"bulk_reuss", number(s.bulk_reuss)},
          {"shear_voigt", number(s.shear_voigt)},    {"shear_reuss", number(s.shear_reuss)},
          {"shear_c44", number(s.shear_voigt_diag)}, {"shear_c11_c12", number(s.shear_diag)}};
}

std::string g6(double x) {
  char b[32];
  std::snprintf(b, sizeof b, "%.6g", x);
  return b;
}
std::string g6(const nlohmann::json& v) {
  return v.is_null() ? "-" : g6(v.get<double>());
}

} // namespace

template <int dim>
nlohmann::json elastic_tensor_json(const VoigtMatrix<dim>& c, const VoigtMatrix<dim>& affine) {
  const ElasticSummary<dim> s = summarize_elastic_tensor<dim>(c);
  const ElasticSummary<dim> a = summarize_elastic_tensor<dim>(affine);
  std::vector<std::string> order;
  for (int i = 0; i < voigt_size<dim>; ++i)
    order.push_back(voigt_name<dim>(i));
  nlohmann::json j = moduli_of(s);
  j["voigt_order"] = order;
  j["c"] = rows_of<dim>(c);
  j["symmetry_deviation"] = s.symmetry_deviation;
  j["eigenvalues"] =
      std::vector<double>(s.eigenvalues.data(), s.eigenvalues.data() + s.eigenvalues.size());
  j["positive_definite"] = s.positive_definite;
  j["c_affine"] = rows_of<dim>(affine);
  j["c_nonaffine"] = rows_of<dim>(VoigtMatrix<dim>(c - affine));
  j["affine"] = moduli_of(a);
  nlohmann::json non = nlohmann::json::object();
  for (const auto& [key, value] : j["affine"].items())
    non[key] = value.is_null() || j[key].is_null()
                   ? nlohmann::json()
                   : nlohmann::json(j[key].template get<double>() - value.template get<double>());
  j["nonaffine"] = non;
  return j;
}

std::vector<std::pair<std::string, std::string>> elastic_tensor_lines(const nlohmann::json& e) {
  if (e.is_null())
    return {{"elastic tensor c_IJ", "- (no response: mechanisms)"}};
  std::vector<std::pair<std::string, std::string>> lines;
  std::string order;
  for (const auto& name : e["voigt_order"])
    order += name.get<std::string>() + " ";
  lines.emplace_back("elastic tensor c_IJ / Pa (K1+K2)", "Voigt order " + order);
  for (std::size_t i = 0; i < e["c"].size(); ++i) {
    std::string row;
    for (const auto& x : e["c"][i])
      row += g6(x) + " ";
    lines.emplace_back("  " + e["voigt_order"][i].get<std::string>(), row);
  }
  lines.emplace_back("c: asymmetry, min eig., pos. def.",
                     g6(e["symmetry_deviation"]) + ", " + g6(e["eigenvalues"][0]) + ", " +
                         (e["positive_definite"].get<bool>() ? "yes" : "no"));
  lines.emplace_back("B Voigt, Reuss / Pa", g6(e["bulk_voigt"]) + ", " + g6(e["bulk_reuss"]));
  lines.emplace_back("G Voigt, Reuss / Pa", g6(e["shear_voigt"]) + ", " + g6(e["shear_reuss"]));
  lines.emplace_back("G c44-type, (c11-c12)/2-type / Pa",
                     g6(e["shear_c44"]) + ", " + g6(e["shear_c11_c12"]));
  const auto& a = e["affine"];
  const auto& n = e["nonaffine"];
  lines.emplace_back("affine B, G44, (c11-c12)/2 / Pa", g6(a["bulk_voigt"]) + ", " +
                                                            g6(a["shear_c44"]) + ", " +
                                                            g6(a["shear_c11_c12"]));
  lines.emplace_back("non-affine dB, dG44, d(c11-c12)/2", g6(n["bulk_voigt"]) + ", " +
                                                              g6(n["shear_c44"]) + ", " +
                                                              g6(n["shear_c11_c12"]));
  return lines;
}

template nlohmann::json elastic_tensor_json<2>(const VoigtMatrix<2>&, const VoigtMatrix<2>&);
template nlohmann::json elastic_tensor_json<3>(const VoigtMatrix<3>&, const VoigtMatrix<3>&);

} // namespace granpack
