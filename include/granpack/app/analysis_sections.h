#pragma once
// The sections of `granpack analyze` (docs/analysis.md), each computing its quantities from a
// PackingView on every rank (collective on the view's communicator) and returning them as
// JSON (identical on every rank).
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "granpack/analysis/force_sign_classes.h"
#include "granpack/packing/packing_view.h"

namespace granpack {

/// What every result file starts with: file, dimension, n, friction, phi, pressure.
template <int dim>
nlohmann::json packing_summary(const PackingView<dim>& v, const std::filesystem::path& file) {
  return {{"file", file.string()},
          {"dimension", dim},
          {"n", v.n},
          {"friction", std::isinf(v.law.friction.mu) ? nlohmann::json("inf")
                                                     : nlohmann::json(v.law.friction.mu)},
          {"phi", v.phi},
          {"pressure", v.pressure}};
}

/// Contact network and forces: counts, rattlers, z, z*, x_i under treatments I-III, H/N_f
/// (eq. 37), P(f), Z(alpha) (eq. 27), strong/weak split (table VI), eq. (22), Delta Phi (eq. 28).
template <int dim> nlohmann::json analyze_network(const PackingView<dim>& v);

struct PairOptions {
  double r_max = 3.0;      ///< g(r) range / a
  double bin_width = 0.01; ///< g(r) bin / a
};
/// g(r) and z(h) for all grains (treatment I) and without rattlers (III), fits of eq. (35).
template <int dim> nlohmann::json analyze_pairs(const PackingView<dim>& v, const PairOptions& o);

/// All interactions (contacts and cohesive distant pairs) with N = N^e + N^a ([GRC] sec. IV):
/// z+, z-, z0, the distribution of N / F_s and of the force angle (fig. 9, 15), Rumpf's
/// eq. (17), the percolation threshold F_perc (sec. IV B 1).
template <int dim> nlohmann::json analyze_interactions(const PackingView<dim>& v);

/// Part of analyze_interactions: table VI's force means by sign class (`force_means`) and the
/// fractions x_k of grains with k interactions (`x_k`, figs. 3 and 6) and with k stressed ones
/// (`x_k_stressed`, |N| above the tolerance), from the rank's sums and per-grain counts (local
/// indices, ghosts included). Collective.
template <int dim>
nlohmann::json interaction_classes(const PackingView<dim>& v, ForceSignSums sums,
                                   std::vector<double> all, std::vector<double> stressed,
                                   double force_scale);

struct DensityOptions {
  bool enabled = true;           ///< 2D only; off with --no-density
  double spacing = 0.01;         ///< mesh spacing / a ([GRC] V C: about a/100)
  double max_nodes = 6.4e7;      ///< coarser mesh beyond this (about 1.5 GB of FFT arrays)
  double k_max_wavelength = 1.0; ///< the fit of eq. (28) stops at k = 2 pi / (this * a)
  int bins = 60;                 ///< logarithmic |k| bins of I(k)
  double r_bin = 0.25;           ///< C(r) bin width / a
  double r_min = 1.0;            ///< the real-space fit of eq. (27) starts at r = this * a
};
/// 2D density fluctuations ([GRC] sec. V): I(k) (eq. 25) and C(r) (eq. 24), the fits of eq. (28)
/// and of eq. (27) giving d_F and xi, hole radii and <R>_w (eq. 29-30). Collective; computed on
/// rank 0.
nlohmann::json analyze_density(const PackingView<2>& v, const DensityOptions& o);

/// Triangles and tetrahedra of the backbone contact network per backbone grain ([AR] III D).
template <int dim> nlohmann::json analyze_motifs(const PackingView<dim>& v);

/// Bond-orientational order (eq. 31-34, tables II, VII, VIII) for d_c = 1.35 a and 1.40 a.
nlohmann::json analyze_order(const PackingView<3>& v);

} // namespace granpack
