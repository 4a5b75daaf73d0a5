#include "granpack/analysis/force_statistics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "granpack/contact/derived_constants.h"
#include "granpack/core/error.h"

namespace granpack {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr int kMomentOffset = 4; // [0] count, [1] sum N, [2] sum N h, [3] sum N^{5/3}

double ratio_or_nan(double num, double den) {
  return den > 0 ? num / den : kNaN;
}

} // namespace

// ---------------------------------------------------------------------------------------------
// Pass 1

ForceMomentSums::ForceMomentSums(std::vector<double> alphas)
    : alphas_(std::move(alphas)), sums_(kMomentOffset + alphas_.size(), 0.0) {}

void ForceMomentSums::add(const ContactForceSample& c) {
  const double n = c.normal_force;
  sums_[0] += 1.0;
  sums_[1] += n;
  sums_[2] += n * c.deflection;
  sums_[3] += std::pow(n, 5.0 / 3.0);
  for (std::size_t k = 0; k < alphas_.size(); ++k)
    sums_[kMomentOffset + k] += std::pow(n, alphas_[k]);
}

void ForceMomentSums::add(std::span<const ContactForceSample> contacts) {
  for (const auto& c : contacts)
    add(c);
}

void ForceMomentSums::merge(const ForceMomentSums& other) {
  GRANPACK_CHECK(other.alphas_ == alphas_, "ForceMomentSums::merge: different moment orders");
  for (std::size_t k = 0; k < sums_.size(); ++k)
    sums_[k] += other.sums_[k];
}

double ForceMomentSums::mean_normal_force() const {
  return ratio_or_nan(sums_[1], sums_[0]);
}

// ---------------------------------------------------------------------------------------------
// Pass 2

ForceSplitSums::ForceSplitSums(double mean_normal_force, ForceBins bins)
    : mean_(mean_normal_force), bins_(bins),
      sums_(static_cast<std::size_t>(bins.bins + 2 + kPopulations * kPerPopulation), 0.0) {
  GRANPACK_CHECK(bins.bins > 0 && bins.f_max > 0, "ForceBins: need bins > 0 and f_max > 0 (got "
                                                      << bins.bins << ", " << bins.f_max << ")");
}

void ForceSplitSums::add(const ContactForceSample& c) {
  const double n = c.normal_force;
  const auto nb = static_cast<std::size_t>(bins_.bins);
  // Histogram of f = N/<N>. With <N> <= 0 or NaN (no contacts anywhere) f is meaningless and
  // lands in the overflow bin; finish() reports NaN statistics in that case anyway.
  const double f = n / mean_;
  std::size_t bin = nb; // overflow
  if (f < 0) {
    bin = nb + 1;
  } else if (f < bins_.f_max) {
    bin = std::min(nb - 1, static_cast<std::size_t>(f / (bins_.f_max / bins_.bins)));
  }
  sums_[bin] += 1.0;

  const bool strong = n > mean_;
  auto accumulate = [&](ForcePopulation p) {
    double* s = sums_.data() + nb + 2 + static_cast<std::size_t>(p) * kPerPopulation;
    s[0] += 1.0;
    if (strong)
      s[1] += 1.0;
    s[2] += n;
    if (n > 0) {
      const double mobilization = c.tangential_force / n;
      if (strong) {
        s[3] += mobilization;
        s[4] += 1.0;
      } else {
        s[5] += mobilization;
        s[6] += 1.0;
      }
    }
  };
  accumulate(ForcePopulation::all);
  if (c.coordination_i == 2 || c.coordination_j == 2)
    accumulate(ForcePopulation::divalent);
  if (c.coordination_i == 3 || c.coordination_j == 3)
    accumulate(ForcePopulation::trivalent);
}

void ForceSplitSums::add(std::span<const ContactForceSample> contacts) {
  for (const auto& c : contacts)
    add(c);
}

void ForceSplitSums::merge(const ForceSplitSums& other) {
  const bool same_mean = other.mean_ == mean_ || (std::isnan(other.mean_) && std::isnan(mean_));
  GRANPACK_CHECK(other.sums_.size() == sums_.size() && other.bins_.f_max == bins_.f_max &&
                     same_mean,
                 "ForceSplitSums::merge: different bins or <N>");
  for (std::size_t k = 0; k < sums_.size(); ++k)
    sums_[k] += other.sums_[k];
}

double ForceSplitSums::population(ForcePopulation p, int q) const {
  return sums_[static_cast<std::size_t>(bins_.bins + 2 + static_cast<int>(p) * kPerPopulation + q)];
}

// ---------------------------------------------------------------------------------------------
// Final quantities

template <int dim> double delta_phi_eq28(double phi, double z, double z_5_3, double kappa) {
  // eq. (26) with N = Ẽ sqrt(a) h^{3/2}/3 and <N> from eq. (22) (docs/analysis-statistics.md).
  const double c = dim == 3 ? std::pow(3.0, 5.0 / 3.0) : 2.0 * std::pow(3.0, 2.0 / 3.0);
  return c * std::cbrt(phi) * z_5_3 * std::pow(std::numbers::pi / z, 2.0 / 3.0) / kappa;
}

template <int dim>
ForceStatistics finish_force_statistics(const ForceMomentSums& pass1, const ForceSplitSums& pass2,
                                        const PackingScales& s) {
  ForceStatistics r;
  const auto& m = pass1.sums();
  const double nc = m[0];
  r.contacts = nc;
  r.mean_normal_force = pass1.mean_normal_force();
  const double mean = r.mean_normal_force;
  r.coordination = s.n_grains > 0 ? 2.0 * nc / s.n_grains : kNaN;
  r.alphas = pass1.alphas();
  for (std::size_t k = 0; k < r.alphas.size(); ++k)
    r.moments.push_back(ratio_or_nan(m[kMomentOffset + k], nc) / std::pow(mean, r.alphas[k]));
  r.z_5_3 = ratio_or_nan(m[3], nc) / std::pow(mean, 5.0 / 3.0);

  // P(f)
  const auto& h = pass2.sums();
  const int nb = pass2.bins().bins;
  const double width = pass2.bins().f_max / nb;
  for (int k = 0; k <= nb; ++k)
    r.f_edges.push_back(k * width);
  for (int k = 0; k < nb; ++k)
    r.pdf.push_back(ratio_or_nan(h[static_cast<std::size_t>(k)], nc * width));
  r.fraction_above = ratio_or_nan(h[static_cast<std::size_t>(nb)], nc);
  r.fraction_below = ratio_or_nan(h[static_cast<std::size_t>(nb + 1)], nc);

  // Strong / weak split ([AR] table VI); forces normalised by P a^{dim-1}.
  const double force_scale = pressure_force(dim, s.diameter, s.pressure);
  auto split = [&](ForcePopulation p) {
    StrongWeakSplit w;
    const auto q = [&](int i) { return pass2.population(p, i); };
    w.contacts = q(0);
    w.strong_fraction = ratio_or_nan(q(1), q(0));
    w.strong_mobilization = ratio_or_nan(q(3), q(4));
    w.weak_mobilization = ratio_or_nan(q(5), q(6));
    w.mean_normal_force = ratio_or_nan(q(2), q(0)) / force_scale;
    return w;
  };
  r.all = split(ForcePopulation::all);
  r.divalent = split(ForcePopulation::divalent);
  r.trivalent = split(ForcePopulation::trivalent);

  // eq. (22) and its 2D analogue (branch vectors of length a, docs/analysis-statistics.md).
  r.pressure_eq22 = r.coordination * s.solid_fraction * mean /
                    (std::numbers::pi * grain_section(dim, s.diameter));
  r.eq22_ratio = r.pressure_eq22 / s.pressure;

  // eq. (26): sum N h / Omega = P DeltaPhi / Phi.
  r.delta_phi_eq26 = s.solid_fraction * m[2] / (s.volume * s.pressure);
  r.phi0_eq26 = s.solid_fraction - r.delta_phi_eq26;

  // eq. (21), (28).
  if (s.e_tilde > 0 && s.pressure > 0) {
    const double stiffness = dim == 3 ? s.e_tilde : s.e_tilde * s.diameter;
    r.kappa = hertz_stiffness_number(stiffness, s.pressure);
    r.delta_phi_eq28 = delta_phi_eq28<dim>(s.solid_fraction, r.coordination, r.z_5_3, r.kappa);
  } else {
    r.kappa = kNaN;
    r.delta_phi_eq28 = kNaN;
  }
  r.phi0_eq28 = s.solid_fraction - r.delta_phi_eq28;
  return r;
}

// ---------------------------------------------------------------------------------------------
// eq. (37)

template <int dim>
Hyperstaticity hyperstaticity(std::int64_t backbone_contacts, std::int64_t backbone_grains,
                              std::int64_t divalent_grains, bool frictional) {
  GRANPACK_CHECK(backbone_contacts >= 0 && backbone_grains >= 0 && divalent_grains >= 0 &&
                     divalent_grains <= backbone_grains,
                 "hyperstaticity: bad counts (contacts " << backbone_contacts << ", grains "
                                                         << backbone_grains << ", divalent "
                                                         << divalent_grains << ")");
  constexpr double d = dim;
  const auto nc = static_cast<double>(backbone_contacts);
  const auto n = static_cast<double>(backbone_grains);
  Hyperstaticity h;
  h.z_star = ratio_or_nan(2.0 * nc, n);
  if (frictional) {
    // Mechanisms beyond the trivial ones: one rolling motion per divalent sphere (3D only).
    const double k2 = dim == 3 ? static_cast<double>(divalent_grains) : 0.0;
    h.dof = n * d * (d + 1) / 2;
    h.degree = d * nc + k2 - h.dof;
    h.z0_star = (d + 1) - ratio_or_nan(2.0 * k2, d * n);
    h.z_star_corrected = h.z_star + (d + 1) - h.z0_star;
  } else {
    h.dof = n * d;
    h.degree = nc - h.dof;
    h.z0_star = 2 * d;
    h.z_star_corrected = h.z_star;
  }
  h.per_dof = ratio_or_nan(h.degree, h.dof);
  return h;
}

template ForceStatistics finish_force_statistics<2>(const ForceMomentSums&, const ForceSplitSums&,
                                                    const PackingScales&);
template ForceStatistics finish_force_statistics<3>(const ForceMomentSums&, const ForceSplitSums&,
                                                    const PackingScales&);
template double delta_phi_eq28<2>(double, double, double, double);
template double delta_phi_eq28<3>(double, double, double, double);
template Hyperstaticity hyperstaticity<2>(std::int64_t, std::int64_t, std::int64_t, bool);
template Hyperstaticity hyperstaticity<3>(std::int64_t, std::int64_t, std::int64_t, bool);

} // namespace granpack
