// `granpack analyze`, interaction section: the force statistics of [GRC] sec. IV A-B on all
// interactions (contacts and cohesive distant pairs) with the total normal force
// N = N^e + N^a (kernels in analysis/interaction_forces). Histograms and sums are reduced
// over the ranks; the percolation threshold needs the whole network, so the interactions
// (two ids, the scaled branch vector, |F|) are gathered on rank 0 with the grain positions
// (like the aggregation stage's cluster count: meant for the 10^3-10^5 grains of [GRC]).
#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "granpack/analysis/interaction_forces.h"
#include "granpack/app/analysis_sections.h"
#include "granpack/comm/broadcast.h"
#include "granpack/comm/communicator.h"
#include "granpack/comm/gather.h"
#include "granpack/comm/reduce.h"
#include "granpack/contact/derived_constants.h"

namespace granpack {

namespace {

void reduce(Histogram& h, MPI_Comm world) {
  global_sum_in_place(world, h.counts);
  double tails[2] = {h.below, h.above};
  global_sum_in_place(world, tails);
  h.below = tails[0];
  h.above = tails[1];
}

nlohmann::json histogram_json(const Histogram& h) {
  const double t = h.total();
  return {{"edges", h.edges()},
          {"pdf", h.pdf()},
          {"count", t},
          {"fraction_below", t > 0 ? h.below / t : 0.0},
          {"fraction_above", t > 0 ? h.above / t : 0.0}};
}

template <int dim>
PercolationResult percolation(const PackingView<dim>& v, const std::vector<double>& mine) {
  const std::vector<double> all = gather_values(mine, v.world);
  const auto grains = gather_particles(v.particles(), v.world);
  const int rank = rank_of(v.world);
  double out[3] = {0, 0, 0};
  if (rank == 0) {
    std::unordered_map<GlobalId, std::int64_t> dense;
    for (std::size_t k = 0; k < grains.size(); ++k)
      dense[grains[k].id] = std::int64_t(k);
    constexpr std::size_t stride = 3 + dim;
    std::vector<PercolationEdge<dim>> edges(all.size() / stride);
    for (std::size_t e = 0; e < edges.size(); ++e) {
      const double* rec = &all[e * stride];
      auto& ed = edges[e];
      ed.i = dense.at(GlobalId(rec[0]));
      ed.j = dense.at(GlobalId(rec[1]));
      for (int a = 0; a < dim; ++a) // the image of j that the branch vector points to
        ed.shift[a] =
            int(std::lround(rec[2 + a] - (grains[ed.j].position[a] - grains[ed.i].position[a])));
      ed.force = rec[2 + dim];
    }
    const PercolationResult r =
        percolation_threshold<dim>(std::move(edges), std::int64_t(grains.size()));
    out[0] = r.threshold_any;
    out[1] = r.threshold_all;
    out[2] = double(r.edges_at_any);
  }
  broadcast_in_place(v.world, out);
  return {out[0], out[1], std::int64_t(out[2])};
}

} // namespace

template <int dim> nlohmann::json analyze_interactions(const PackingView<dim>& v) {
  const auto& p = v.particles();
  const double n = double(v.n);
  const double f0 = v.contact_law.cohesion_force;
  // [GRC] II D: forces are judged against F1 = max(F0, |P| a^(D-1)); "vanishing" below 1e-4 F1.
  const double f1 = force_scale_f1(dim, v.diameter, std::abs(v.pressure), f0);
  const double tolerance = 1e-4 * f1;

  // First pass: counts, sums, the force scale without cohesion (<N^e> over the contacts).
  double sums[8] = {0, 0, 0, 0,
                    0, 0, 0, 0}; // contacts, distant, plus, minus, zero, sum N, sum N^e, N^e>0
  std::vector<double> records;
  for (const auto& c : v.contacts) {
    const double N = c.total_normal_force();
    sums[c.distant ? 1 : 0] += 1;
    sums[N > tolerance ? 2 : N < -tolerance ? 3 : 4] += 1;
    sums[5] += N;
    if (!c.distant)
      sums[6] += c.normal_force, sums[7] += 1;
  }
  double grain_sums[2] = {0, 0}; // sum d, sum d^dim over owned grains
  for (std::size_t i = 0; i < p.n_owned(); ++i) {
    const double d = 2 * p.radius[i];
    grain_sums[0] += d;
    grain_sums[1] += std::pow(d, dim);
  }
  global_sum_in_place(v.world, sums);
  global_sum_in_place(v.world, grain_sums);
  const double interactions = sums[0] + sums[1];
  nlohmann::json j;
  j["cohesion_force"] = f0;
  j["contacts"] = sums[0];
  j["distant"] = sums[1];
  j["z"] = 2 * interactions / n;
  j["z_plus"] = 2 * sums[2] / n;
  j["z_minus"] = 2 * sums[3] / n;
  j["z_zero"] = 2 * sums[4] / n;
  j["vanishing_tolerance"] = tolerance;
  if (interactions == 0)
    return j;
  const double mean_elastic = sums[7] > 0 ? sums[6] / sums[7] : 0.0;
  const double fs = f0 > 0 ? f0 : mean_elastic;
  j["force_scale"] = fs;
  j["force_scale_is"] = f0 > 0 ? "F0" : "<N^e>";
  j["mean_elastic_normal_force"] = mean_elastic;

  // Rumpf (eq. 17) with the sample's own diameter moments and the z of all interactions.
  const double mean_N = sums[5] / interactions;
  const double mean_d = grain_sums[0] / n, mean_dD = grain_sums[1] / n;
  const double predicted =
      rumpf_mean_force(v.pressure, 2 * interactions / n, v.phi, mean_d, mean_dD);
  j["rumpf"] = {{"mean_normal_force", mean_N},
                {"predicted_eq17", predicted},
                {"relative_error", predicted != 0 ? mean_N / predicted - 1 : std::nan("")},
                {"mean_diameter", mean_d},
                {"mean_diameter_pow_dim", mean_dD}};
  if (fs <= 0)
    return j;

  // Second pass: distributions and the percolation records.
  Histogram normal(-1.5, 3.5, 100), angle(0.0, 180.0, 36);
  double counts[2] = {0, 0}; // |F| < tolerance, |N| > F_s / 10
  ForceSignSums signs;       // table VI
  std::vector<double> per_grain(p.size(), 0.0), per_grain_stressed(p.size(), 0.0); // x_k
  for (const auto& c : v.contacts) {
    const double N = c.total_normal_force();
    const Vec<dim> nrm = c.branch.normalized();
    const double T = (c.tangential_force - c.tangential_force.dot(nrm) * nrm).norm();
    const double F = std::hypot(N, T);
    signs.add(N, T, tolerance);
    per_grain[c.i] += 1, per_grain[c.j] += 1;
    if (std::abs(N) > tolerance)
      per_grain_stressed[c.i] += 1, per_grain_stressed[c.j] += 1;
    normal.add(N / fs);
    if (F < tolerance)
      counts[0] += 1;
    else
      angle.add(force_angle_degrees(N, T));
    if (std::abs(N) > 0.1 * fs)
      counts[1] += 1;
    records.push_back(double(p.id[c.i]));
    records.push_back(double(p.id[c.j]));
    for (int a = 0; a < dim; ++a)
      records.push_back(c.branch[a] / v.system.cell.length[a]);
    records.push_back(F);
  }
  reduce(normal, v.world);
  reduce(angle, v.world);
  global_sum_in_place(v.world, counts);
  j["normal_force_pdf"] = histogram_json(normal); // N / F_s
  j["force_angle_pdf"] = histogram_json(angle);   // degrees, interactions with |F| >= tolerance
  j["fraction_vanishing"] = counts[0] / interactions;
  j["fraction_above_tenth"] = counts[1] / interactions;
  j.update(interaction_classes(v, signs, std::move(per_grain), std::move(per_grain_stressed), fs));
  const PercolationResult perc = percolation(v, records);
  j["F_perc_over_Fs"] = perc.threshold_any / fs;
  j["F_perc_all_directions_over_Fs"] = perc.threshold_all / fs;
  j["F_perc_interactions"] = perc.edges_at_any;
  return j;
}

template nlohmann::json analyze_interactions<2>(const PackingView<2>&);
template nlohmann::json analyze_interactions<3>(const PackingView<3>&);

} // namespace granpack
