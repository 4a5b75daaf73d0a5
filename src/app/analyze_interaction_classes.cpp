// `granpack analyze`, interaction section, the parts of [GRC] that were computed by hand: the
// force means of table VI by sign class and the local coordinations x_k of figs. 3 and 6. The
// interaction loop of analyze_interactions fills the sums and the per-grain counts (local
// indices, ghosts included); this reduces them over the ranks.
#include <cmath>

#include "granpack/analysis/force_sign_classes.h"
#include "granpack/app/analysis_sections.h"
#include "granpack/comm/reduce.h"

namespace granpack {

namespace {

nlohmann::json num(double x) {
  return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr);
}

/// Fractions of the n grains with k = 0, 1, ... counted interactions (the last bin collects
/// 15 and more).
template <int dim> nlohmann::json fractions(const PackingView<dim>& v, std::vector<double> counts) {
  v.halo.reverse_values(counts, *v.decomposition); // ghosts' counts to their owners
  std::vector<double> h(16, 0.0);
  for (std::size_t i = 0; i < v.particles().n_owned(); ++i)
    h[std::min<std::size_t>(h.size() - 1, std::size_t(std::lround(counts[i])))] += 1;
  global_sum_in_place(v.world, h);
  nlohmann::json x = nlohmann::json::object();
  for (std::size_t k = 0; k < h.size(); ++k)
    if (h[k] > 0)
      x[std::to_string(k)] = h[k] / double(v.n);
  return x;
}

} // namespace

template <int dim>
nlohmann::json interaction_classes(const PackingView<dim>& v, ForceSignSums sums,
                                   std::vector<double> all, std::vector<double> stressed,
                                   double force_scale) {
  global_sum_in_place(v.world, sums.sums);
  const double total =
      sums.sums[0] + sums.sums[ForceSignSums::fields] + sums.sums[2 * ForceSignSums::fields];
  nlohmann::json means;
  for (auto [name, c] : {std::pair{"repulsive", ForceSign::repulsive},
                         std::pair{"attractive", ForceSign::attractive},
                         std::pair{"vanishing", ForceSign::vanishing}}) {
    const ForceSignMeans m = force_sign_means(sums, c);
    means[name] = {
        {"count", m.count},
        {"mean_abs_N_over_Fs", num(m.mean_normal / force_scale)},
        {"rms_N_over_Fs", num(m.rms_normal / force_scale)},
        // The class's sum of |N| over all interactions: <|N|> z_class / z.
        {"sum_abs_N_over_all_interactions_over_Fs",
         total > 0 ? num(m.mean_normal * m.count / total / force_scale) : nlohmann::json(nullptr)},
        {"mean_abs_T_over_Fs", num(m.mean_tangential / force_scale)},
        {"rms_T_over_Fs", num(m.rms_tangential / force_scale)}};
  }
  return {{"force_means", means},
          {"x_k", fractions(v, std::move(all))},
          {"x_k_stressed", fractions(v, std::move(stressed))}};
}

template nlohmann::json interaction_classes<2>(const PackingView<2>&, ForceSignSums,
                                               std::vector<double>, std::vector<double>, double);
template nlohmann::json interaction_classes<3>(const PackingView<3>&, ForceSignSums,
                                               std::vector<double>, std::vector<double>, double);

} // namespace granpack
