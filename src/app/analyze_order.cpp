// `granpack analyze`, order section: bond-orientational order of [AR] sec. III D and app. D
// (kernels in analysis/bond_order). Per owned grain the bonds within d_c give Q4, Q6 and the
// normalised q6; the q6 of ghosts come from their owners (halo), so crystalline bonds are
// decided identically on both sides. Crystalline clusters are found on rank 0 from the few
// crystalline grains and their crystalline bonds.
#include <array>
#include <cstdio>

#include "granpack/analysis/bond_order.h"
#include "granpack/app/analysis_sections.h"
#include "granpack/comm/broadcast.h"
#include "granpack/comm/communicator.h"
#include "granpack/comm/gather.h"
#include "granpack/comm/qbar_exchange.h"
#include "granpack/comm/reduce.h"

namespace granpack {

namespace {

struct OrderAtCutoff {
  nlohmann::json table2;                     // Z, Z_cr, Q6, Q6_loc, ... (table II)
  std::array<double, 3 * 3> window_counts{}; // [sample F, D, B] x [dis, fcc, hcp]
};

OrderAtCutoff order_at(const PackingView<3>& v, double dc_over_a) {
  const auto& p = v.particles();
  const std::size_t nown = p.n_owned();
  std::vector<BondNeighborhood> hood(nown);
  for (std::size_t i = 0; i < nown; ++i)
    hood[i].id = p.id[i];
  for_each_neighbor(v, dc_over_a * v.diameter,
                    [&](std::size_t i, std::size_t j, const Vec<3>& r, double) {
                      hood[i].bonds.push_back(r);
                      hood[i].neighbor_ids.push_back(p.id[j]);
                    });
  std::vector<LocalBondOrder> q6(nown), q4(nown);
  for (std::size_t i = 0; i < nown; ++i) {
    q6[i] = local_q(hood[i], 6);
    q4[i] = local_q(hood[i], 4);
  }
  const QBarTable table = exchange_qbar(p, q6, v.halo, *v.decomposition);
  BondOrderTally tally;
  std::vector<double> cluster_data; // id, number of crystalline neighbours, their ids
  OrderAtCutoff out;
  const AsteSample samples[3] = {AsteSample::F, AsteSample::D, AsteSample::B};
  const bool tabulated = std::abs(dc_over_a - std::round(dc_over_a * 10) / 10) < 1e-9 &&
                         dc_over_a > 1.05 && dc_over_a < 1.45;
  std::vector<std::vector<OrderWindow>> windows; // per Aste sample, when d_c is tabulated
  if (tabulated)
    for (AsteSample sample : samples)
      windows.push_back(windows_for(sample, dc_over_a));
  for (std::size_t i = 0; i < nown; ++i) {
    const auto cryst = crystalline_neighbors(hood[i], table);
    tally.add(q6[i], int(cryst.size()));
    if (cryst.size() >= 7) {
      cluster_data.push_back(double(p.id[i]));
      cluster_data.push_back(double(cryst.size()));
      for (GlobalId id : cryst)
        cluster_data.push_back(double(id));
    }
    for (std::size_t s = 0; s < windows.size(); ++s)
      for (std::size_t w : windows_containing(q4[i].Q, q6[i].Q, windows[s]))
        out.window_counts[3 * s + w] += 1;
  }
  std::vector<double> packed = tally.packed();
  global_sum_in_place(v.world, packed);
  tally = BondOrderTally::unpacked(packed);
  global_sum_in_place(v.world, out.window_counts);

  // Clusters on rank 0.
  const int rank = rank_of(v.world);
  const std::vector<double> all = gather_values(cluster_data, v.world);
  double mass_average = 0;
  if (rank == 0) {
    std::vector<GlobalId> grains;
    std::vector<std::pair<GlobalId, GlobalId>> bonds;
    for (std::size_t k = 0; k < all.size();) {
      const auto id = GlobalId(all[k]);
      const auto nb = std::size_t(all[k + 1]);
      grains.push_back(id);
      for (std::size_t b = 0; b < nb; ++b)
        bonds.emplace_back(id, GlobalId(all[k + 2 + b]));
      k += 2 + nb;
    }
    mass_average = crystalline_clusters(grains, bonds).mass_average_size;
  }
  mass_average = broadcast_value(v.world, mass_average);
  out.table2 = {{"Z", tally.z()},
                {"Z_cr", tally.z_cr()},
                {"Q6_global", tally.q6_global()},
                {"Q6_local_mean", tally.q6_loc()},
                {"Q6_local_crystalline", tally.q6_loc_cr()},
                {"crystalline_fraction", tally.x_cr()},
                {"cluster_mass_average", mass_average}};
  if (tabulated) {
    const char* names[3] = {"F", "D", "B"};
    nlohmann::json w;
    for (int s = 0; s < 3; ++s)
      w[std::string("aste_") + names[s]] = {
          {"dis", out.window_counts[std::size_t(3 * s)] / double(v.n)},
          {"fcc", out.window_counts[std::size_t(3 * s + 1)] / double(v.n)},
          {"hcp", out.window_counts[std::size_t(3 * s + 2)] / double(v.n)}};
    out.table2["windows"] = w;
  }
  // Q4 mean for the summary.
  double q4sum[2] = {0, 0};
  for (std::size_t i = 0; i < nown; ++i)
    if (q4[i].n_bonds > 0)
      q4sum[0] += q4[i].Q, q4sum[1] += 1;
  global_sum_in_place(v.world, q4sum);
  out.table2["Q4_local_mean"] = q4sum[1] > 0 ? q4sum[0] / q4sum[1] : 0.0;
  return out;
}

} // namespace

nlohmann::json analyze_order(const PackingView<3>& v) {
  nlohmann::json j;
  for (double dc : {1.1, 1.2, 1.3, 1.35, 1.4}) {
    char key[16];
    std::snprintf(key, sizeof key, "%.2f", dc);
    j[key] = order_at(v, dc).table2;
  }
  // The summary keys use d_c = 1.40 a.
  const auto& ref = j["1.40"];
  for (const char* k : {"Q4_local_mean", "Q6_local_mean", "Q6_global", "crystalline_fraction"})
    j[k] = ref[k];
  return j;
}

} // namespace granpack
