// `granpack analyze`, network section: coordination under the three treatments of rattlers
// of [AR] sec. III B-C, force statistics (kernels in analysis/force_statistics).
#include <cmath>
#include <numbers>

#include "granpack/analysis/force_statistics.h"
#include "granpack/app/analysis_sections.h"
#include "granpack/comm/reduce.h"
#include "granpack/contact/derived_constants.h"

namespace granpack {

namespace {

nlohmann::json fractions(std::vector<double> hist, double n, MPI_Comm world) {
  global_sum_in_place(world, hist);
  nlohmann::json xi = nlohmann::json::object();
  for (std::size_t k = 0; k < hist.size(); ++k)
    if (hist[k] > 0)
      xi[std::to_string(k)] = n > 0 ? hist[k] / n : 0.0;
  return xi;
}

/// A number, or null when undefined (NaN: e.g. M1 when no contact is above the mean).
nlohmann::json num(double x) {
  return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr);
}

nlohmann::json split_json(const StrongWeakSplit& s) {
  return {{"contacts", s.contacts},
          {"X1", num(s.strong_fraction)},
          {"M1", num(s.strong_mobilization)},
          {"M2", num(s.weak_mobilization)},
          {"N_over_Pa2", num(s.mean_normal_force)}};
}

} // namespace

template <int dim> nlohmann::json analyze_network(const PackingView<dim>& v) {
  const auto& p = v.particles();
  const auto& m = v.backbone.metrics;
  const double n = double(v.n);
  constexpr std::size_t max_z = 16;

  // x_i: I, backbone contacts per grain, rattlers as x0; II, every force-carrying contact
  // (after a fix_rattlers stage this is [AR]'s treatment II); III, rattlers removed.
  std::vector<double> h1(max_z, 0.0), h2(max_z, 0.0), h3(max_z, 0.0), all_counts(p.size(), 0.0);
  for (const auto& c : v.carrying)
    all_counts[c.i] += 1, all_counts[c.j] += 1;
  v.halo.reverse_values(all_counts, *v.decomposition);
  std::int64_t divalent = 0;
  for (std::size_t i = 0; i < p.n_owned(); ++i) {
    const auto zi =
        std::min<std::size_t>(max_z - 1, std::size_t(std::lround(v.backbone.counts[i])));
    h2[std::min<std::size_t>(max_z - 1, std::size_t(std::lround(all_counts[i])))] += 1;
    if (v.rattler(i)) {
      h1[0] += 1;
    } else {
      h1[zi] += 1;
      h3[zi] += 1;
      divalent += zi == 2;
    }
  }
  divalent = global_sum(v.world, divalent);

  nlohmann::json j;
  j["force_threshold"] = v.force_threshold;
  j["contacts_in_file"] = global_sum(v.world, static_cast<std::int64_t>(v.contacts.size()));
  j["force_carrying_contacts"] = global_sum(v.world, static_cast<std::int64_t>(v.carrying.size()));
  j["backbone_contacts"] = m.backbone_contacts;
  j["rattlers"] = m.rattlers;
  j["x0"] = m.x0;
  j["z"] = m.z;
  j["z_star"] = m.z_star;
  j["x_i"] = fractions(h1, n, v.world);
  j["x_i_all_contacts"] = fractions(h2, n, v.world);
  j["x_i_without_rattlers"] = fractions(h3, n - double(m.rattlers), v.world);
  j["x2"] = double(divalent) / n;
  const Hyperstaticity hs =
      hyperstaticity<dim>(m.backbone_contacts, m.n - m.rattlers, divalent, v.law.friction.mu > 0);
  j["H"] = hs.degree;
  j["H_over_Nf"] = hs.per_dof;

  // Forces on the backbone contacts, two passes.
  std::vector<ContactForceSample> samples;
  for (const auto& c : v.contacts) {
    if (c.normal_force <= v.force_threshold || v.rattler(c.i) || v.rattler(c.j))
      continue;
    const double dist = c.branch.norm();
    const Vec<dim> normal = c.branch / dist;
    const Vec<dim> t = c.tangential_force - c.tangential_force.dot(normal) * normal;
    samples.push_back({c.normal_force, t.norm(), p.radius[c.i] + p.radius[c.j] - dist,
                       int(std::lround(v.backbone.counts[c.i])),
                       int(std::lround(v.backbone.counts[c.j]))});
  }
  ForceMomentSums pass1({5.0 / 3.0, 2.0, 3.0});
  pass1.add(samples);
  global_sum_in_place(v.world, pass1.sums());
  if (pass1.contacts() == 0) {
    j["mean_normal_force"] = j["Z_5_3"] = j["Z_2"] = nullptr;
    return j;
  }
  ForceSplitSums pass2(pass1.mean_normal_force());
  pass2.add(samples);
  global_sum_in_place(v.world, pass2.sums());
  const auto& mat = v.contact_law;
  const double e_tilde =
      mat.normal == NormalLawKind::kHertz && v.deck.sample.distribution == "monodisperse"
          ? e_tilde_of(mat.young_modulus, mat.poisson_ratio)
          : 0.0;
  const ForceStatistics fs = finish_force_statistics<dim>(
      pass1, pass2,
      PackingScales{v.pressure, v.diameter, v.phi, n, v.system.cell.volume(), e_tilde});
  j["mean_normal_force"] = fs.mean_normal_force;
  j["Z_5_3"] = fs.z_5_3;
  nlohmann::json moments = nlohmann::json::object();
  for (std::size_t k = 0; k < fs.alphas.size(); ++k)
    moments[std::to_string(fs.alphas[k])] = fs.moments[k];
  j["Z_alpha"] = moments;
  j["Z_2"] = fs.moments[1];
  j["P_f"] = {{"f_edges", fs.f_edges}, {"pdf", fs.pdf}, {"fraction_above", fs.fraction_above}};
  j["X1"] = num(fs.all.strong_fraction);
  j["M1"] = num(fs.all.strong_mobilization);
  j["M2"] = num(fs.all.weak_mobilization);
  j["divalent_contacts"] = split_json(fs.divalent);
  j["trivalent_contacts"] = split_json(fs.trivalent);
  // Eq. (22) is for equal diameters a; polydisperse packings ([GRC]'s disks) have the general
  // Rumpf relation, eq. (17) of [GRC], in the interaction section.
  if (v.deck.sample.distribution == "monodisperse") {
    j["pressure_eq22"] = fs.pressure_eq22;
    j["eq22_relative_error"] = fs.eq22_ratio - 1;
  } else {
    j["pressure_eq22"] = j["eq22_relative_error"] = nullptr;
  }
  if (e_tilde > 0) {
    j["kappa"] = fs.kappa;
    j["delta_phi"] = fs.delta_phi_eq28;
    j["phi0"] = fs.phi0_eq28;
  } else {
    j["kappa"] = j["delta_phi"] = j["phi0"] = nullptr;
  }
  return j;
}

template nlohmann::json analyze_network<2>(const PackingView<2>&);
template nlohmann::json analyze_network<3>(const PackingView<3>&);

} // namespace granpack
