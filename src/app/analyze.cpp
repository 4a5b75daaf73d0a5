#include "granpack/app/analyze.h"

#include <cmath>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <unordered_map>

#include "granpack/comm/halo.h"
#include "granpack/comm/migration.h"
#include "granpack/comm/reduce.h"
#include "granpack/io/deck.h"
#include "granpack/io/hdf5_store.h"
#include "granpack/io/report.h"
#include "granpack/prep/backbone.h"

namespace granpack {

namespace {

/// Friction coefficient in force when the file was written: the deck's, changed by the
/// `set` stages that ran up to the file's stage.
double friction_of(const Deck& deck, int stage_index) {
  double mu = deck.material.friction;
  for (const auto& st : deck.stages)
    if (st.index <= stage_index)
      if (const auto* s = std::get_if<SetStage>(&st.params); s && s->friction) mu = *s->friction;
  return mu;
}

template <int dim> nlohmann::json analyze(MPI_Comm world, const AnalyzeOptions& opt,
                                         const FileMeta& meta) {
  Configuration<dim> cfg = read_configuration<dim>(world, opt.file);
  const Deck deck = parse_deck(meta.deck_text, opt.file.string() + ":/deck");
  const double mu = friction_of(deck, meta.stage_index);
  const double a = deck.sample.diameter;

  System<dim> sys;
  sys.cell = cfg.cell;
  sys.particles = std::move(cfg.particles);
  sys.contacts = std::move(cfg.contacts);
  Decomposition<dim> d(world, sys.cell.length);
  distribute(sys, d);
  double rmax = 0, volume = 0;
  auto& p = sys.particles;
  for (std::size_t i = 0; i < p.n_owned(); ++i) {
    rmax = std::max(rmax, p.radius[i]);
    volume += dim == 3 ? 4.0 / 3.0 * std::numbers::pi * std::pow(p.radius[i], 3)
                       : std::numbers::pi * p.radius[i] * p.radius[i];
  }
  rmax = global_max(world, rmax);
  const double phi = global_sum(world, volume) / sys.cell.volume();
  Halo<dim> halo;
  // Contacts overlap, so both grains lie within 2 R_max (plus round-off) of each other.
  halo.borders(p, d, Vec<dim>::Constant(2.0 * rmax * (1 + 1e-9)).cwiseQuotient(sys.cell.length));

  // Local index of each contact's two grains: the first is owned (contacts travel with their
  // first grain); of the images of the second, the nearest.
  std::unordered_multimap<GlobalId, std::size_t> where;
  for (std::size_t i = 0; i < p.size(); ++i) where.emplace(p.id[i], i);
  struct Pair {
    std::size_t i, j;
    Vec<dim> r;
    double n;
    Vec<dim> t;
  };
  std::vector<Pair> pairs;
  std::int64_t lost = 0;
  for (std::size_t k = 0; k < sys.contacts.size(); ++k) {
    const auto& key = sys.contacts.key(k);
    std::size_t i = p.size(), j = p.size();
    for (auto [it, end] = where.equal_range(key.first); it != end; ++it)
      if (it->second < p.n_owned()) i = it->second;
    double best = std::numeric_limits<double>::infinity();
    if (i < p.size())
      for (auto [it, end] = where.equal_range(key.second); it != end; ++it) {
        double dist = sys.cell.length.cwiseProduct(p.position[it->second] - p.position[i]).norm();
        if (dist < best) best = dist, j = it->second;
      }
    if (i == p.size() || j == p.size()) {
      ++lost;
      continue;
    }
    const Vec<dim> r = sys.cell.length.cwiseProduct(p.position[j] - p.position[i]);
    pairs.push_back({i, j, r, sys.contacts.state(k).normal_force, sys.contacts.state(k).tangential_force});
  }
  GRANPACK_CHECK(global_sum(world, lost) == 0,
                 opt.file.string() << ": " << global_sum(world, lost)
                                   << " contacts name grains that are not in contact range");

  // Measured (elastic) stress, eq. (8) without the kinetic part.
  Tensor<dim> virial = Tensor<dim>::Zero();
  for (const auto& c : pairs) virial += (c.n * c.r.normalized() + c.t) * c.r.transpose();
  MPI_Allreduce(MPI_IN_PLACE, virial.data(), dim * dim, MPI_DOUBLE, MPI_SUM, world);
  const Tensor<dim> sigma = virial / sys.cell.volume();
  const double pressure = sigma.trace() / dim;
  const double force_scale = (dim == 3 ? a * a : a) * pressure;

  std::vector<CarryingContact> carrying;
  for (const auto& c : pairs)
    if (c.n > opt.threshold * force_scale) carrying.push_back({c.i, c.j, c.n});
  const int min_contacts = mu > 0 ? 2 : dim + 1;
  const Backbone bb = find_backbone(p, halo, d, carrying, min_contacts);
  const auto& m = bb.metrics;

  // Coordination fractions x_i over all grains (x0: rattlers) and force moments Z(alpha).
  std::vector<double> hist(16, 0.0);
  for (std::size_t i = 0; i < p.n_owned(); ++i)
    if (!bb.rattler[i]) hist[std::min<std::size_t>(15, std::size_t(std::lround(bb.counts[i])))] += 1;
  MPI_Allreduce(MPI_IN_PLACE, hist.data(), int(hist.size()), MPI_DOUBLE, MPI_SUM, world);
  std::vector<CarryingContact> backbone;
  for (const auto& c : carrying)
    if (!bb.rattler[c.i] && !bb.rattler[c.j]) backbone.push_back(c);
  double sums[4] = {sum_force_power(backbone, 1.0), sum_force_power(backbone, 5.0 / 3.0),
                    sum_force_power(backbone, 2.0), double(backbone.size())};
  MPI_Allreduce(MPI_IN_PLACE, sums, 4, MPI_DOUBLE, MPI_SUM, world);
  const double nc = std::max(sums[3], 1.0), mean_n = sums[0] / nc;
  const double z53 = (sums[1] / nc) / std::pow(mean_n, 5.0 / 3.0);
  const double z2 = (sums[2] / nc) / (mean_n * mean_n);

  nlohmann::json j;
  j["file"] = opt.file.string();
  j["dimension"] = dim;
  j["n"] = m.n;
  j["friction"] = std::isinf(mu) ? nlohmann::json("inf") : nlohmann::json(mu);
  j["phi"] = phi;
  j["pressure"] = pressure;
  j["force_threshold"] = opt.threshold * force_scale;
  j["contacts_in_file"] = global_sum(world, static_cast<std::int64_t>(pairs.size()));
  j["force_carrying_contacts"] = global_sum(world, static_cast<std::int64_t>(carrying.size()));
  j["backbone_contacts"] = m.backbone_contacts;
  j["rattlers"] = m.rattlers;
  j["x0"] = m.x0;
  j["z"] = m.z;
  j["z_star"] = m.z_star;
  nlohmann::json xi = nlohmann::json::object();
  for (std::size_t k = 0; k < hist.size(); ++k)
    if (hist[k] > 0) xi[std::to_string(k)] = hist[k] / double(m.n);
  j["x_i"] = xi;
  j["x2"] = hist[2] / double(m.n);
  const bool any = sums[3] > 0;  // without force-carrying contacts the moments are undefined
  j["mean_normal_force"] = any ? nlohmann::json(mean_n) : nlohmann::json(nullptr);
  j["Z_5_3"] = any ? nlohmann::json(z53) : nlohmann::json(nullptr);
  j["Z_2"] = any ? nlohmann::json(z2) : nlohmann::json(nullptr);
  if (any && dim == 3 && deck.sample.distribution == "monodisperse") {
    // eq. (22): P = z Phi <N> / (pi a^2), with z over all grains.
    const double p22 = m.z * phi * mean_n / (std::numbers::pi * a * a);
    j["pressure_eq22"] = p22;
    j["eq22_relative_error"] = p22 / pressure - 1;
  }
  return j;
}

std::string table(const nlohmann::json& j) {
  std::string out;
  char buf[160];
  auto row = [&](const char* name, const std::string& value) {
    std::snprintf(buf, sizeof buf, "  %-26s %s\n", name, value.c_str());
    out += buf;
  };
  auto num = [](const nlohmann::json& v) {
    if (v.is_null()) return std::string("-");
    char b[32];
    std::snprintf(b, sizeof b, "%.6g", v.get<double>());
    return std::string(b);
  };
  out += "granpack analyze: " + j["file"].get<std::string>() + "\n";
  row("dimension, n", std::to_string(j["dimension"].get<int>()) + ", " + std::to_string(j["n"].get<long long>()));
  row("friction mu", j["friction"].dump());
  row("solid fraction Phi", num(j["phi"]));
  row("pressure (elastic) / Pa", num(j["pressure"]));
  row("force threshold / N", num(j["force_threshold"]));
  row("contacts: all / carrying", std::to_string(j["contacts_in_file"].get<long long>()) + " / " +
                                      std::to_string(j["force_carrying_contacts"].get<long long>()));
  row("rattler fraction x0", num(j["x0"]));
  row("coordination z", num(j["z"]));
  row("backbone coordination z*", num(j["z_star"]));
  std::string xs;
  for (auto& [k, v] : j["x_i"].items()) xs += "x" + k + "=" + num(v) + " ";
  row("fractions x_i (backbone)", xs);
  row("<N> / N", num(j["mean_normal_force"]));
  row("Z(5/3), Z(2)", num(j["Z_5_3"]) + ", " + num(j["Z_2"]));
  if (j.contains("pressure_eq22"))
    row("eq. (22) z Phi <N>/(pi a^2)", num(j["pressure_eq22"]) + " Pa (relative error " +
                                           num(j["eq22_relative_error"]) + ")");
  return out;
}

}  // namespace

std::string analyze_file(MPI_Comm world, const AnalyzeOptions& options) {
  const FileMeta meta = read_file_meta(world, options.file);
  nlohmann::json j = meta.dimension == 3 ? analyze<3>(world, options, meta)
                                         : analyze<2>(world, options, meta);
  int rank = 0;
  MPI_Comm_rank(world, &rank);
  if (rank == 0) {
    std::cout << table(j);
    if (options.json) write_text_atomically(*options.json, j.dump(2) + "\n");
  }
  return j.dump();
}

}  // namespace granpack
