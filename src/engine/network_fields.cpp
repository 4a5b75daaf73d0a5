#include "granpack/engine/network_fields.h"

#include <algorithm>

#include "granpack/analysis/local_order.h"
#include "granpack/comm/backbone.h"
#include "granpack/comm/cluster_ids.h"
#include "granpack/comm/halo.h"
#include "granpack/comm/qbar_exchange.h"
#include "granpack/comm/reduce.h"
#include "granpack/contact/contact_law_params.h"
#include "granpack/contact/derived_constants.h"

namespace granpack {

namespace {
/// f.rattler: [AR]'s iterated rule (comm/backbone.h) on the contacts with N^e above
/// 1e-4 F1, F1 = a^(dim-1) P (P the static pressure of these forces) or F0 with cohesion, the
/// threshold `granpack analyze` uses by default.
template <int dim>
void rattler_flags(const RunContext<dim>& ctx, const ParticleStore<dim>& p, const Halo<dim>& halo,
                   NetworkFields<dim>& f) {
  const auto& d = *ctx.decomposition;
  // The static pressure: sum of V_g mean_stress_g over the local grains (ghosts carry the
  // partial sums of their owners) over the cell's volume.
  double local = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    local += grain_volume<dim>(p.radius[i]) * f.mean_stress[i];
  const double pressure = global_sum(ctx.world, local) / ctx.system.cell.volume();
  const double threshold =
      kCarryingThreshold *
      force_scale_f1(dim, ctx.deck->sample.diameter, pressure, ctx.contact_law.cohesion_force);
  std::vector<CarryingContact> carrying;
  for (const auto& c : f.pairs)
    if (c.normal_force > threshold)
      carrying.push_back(c);
  const ContactLaw<dim> law = make_contact_law<dim>(ctx.contact_law);
  const Backbone b =
      find_backbone(p, halo, d, carrying, min_backbone_contacts(dim, law.friction.mu));
  f.rattler.assign(b.rattler.begin(), b.rattler.begin() + static_cast<long>(p.n_owned()));
}

/// f.strong: N > <N>, the mean over the compressive contacts of every rank.
template <int dim> void strong_flags(const RunContext<dim>& ctx, NetworkFields<dim>& f) {
  const auto compressive = static_cast<std::int64_t>(NetworkKind::kCompressive);
  double sums[2] = {0, 0}; // sum of N, number of compressive contacts
  for (std::size_t k = 0; k < f.kind.size(); ++k)
    if (f.kind[k] == compressive) {
      sums[0] += f.normal_force[k];
      sums[1] += 1;
    }
  global_sum_in_place(ctx.world, sums);
  const double mean = sums[1] > 0 ? sums[0] / sums[1] : 0.0;
  f.strong.assign(f.kind.size(), 0.0);
  for (std::size_t k = 0; k < f.kind.size(); ++k)
    f.strong[k] = f.kind[k] == compressive && f.normal_force[k] > mean ? 1.0 : 0.0;
}
/// f.bond_order and f.crystalline of the owned grains (analysis/local_order.h): bonds within
/// kOrderCutoff a among the owned grains and the ghosts of `halo` (a layer at least that wide).
template <int dim>
void order_flags(const RunContext<dim>& ctx, const ParticleStore<dim>& p, const Halo<dim>& halo,
                 NetworkFields<dim>& f) {
  const double d_c = kOrderCutoff * ctx.deck->sample.diameter;
  auto bonds = grain_bonds(ctx.system.cell, p, d_c);
  const std::size_t n = p.n_owned();
  f.bond_order.assign(n, 0.0);
  f.crystalline.assign(n, 0.0);
  if constexpr (dim == 2) {
    for (std::size_t i = 0; i < n; ++i) {
      f.bond_order[i] = psi6_modulus(bonds[i].bonds);
      f.crystalline[i] = f.bond_order[i] >= kCrystallinePsi6 ? 1.0 : 0.0;
    }
  } else {
    // [AR]'s rule as `granpack analyze` applies it (its x_cr is the mean of this column).
    std::vector<BondNeighborhood> hood(n);
    std::vector<LocalBondOrder> q6(n);
    for (std::size_t i = 0; i < n; ++i) {
      hood[i] = {bonds[i].id, std::move(bonds[i].bonds), std::move(bonds[i].neighbor_ids)};
      q6[i] = local_q(hood[i], 6);
      f.bond_order[i] = q6[i].Q;
    }
    const QBarTable table = exchange_qbar(p, q6, halo, *ctx.decomposition);
    const int min_bonds = BondOrderParams{}.min_crystalline_bonds;
    for (std::size_t i = 0; i < n; ++i)
      f.crystalline[i] = int(crystalline_neighbors(hood[i], table).size()) >= min_bonds ? 1.0 : 0.0;
  }
}
} // namespace

template <int dim>
std::optional<NetworkFields<dim>> network_fields(const RunContext<dim>& ctx,
                                                 const ContactStore<dim>& contacts) {
  const auto& sys = ctx.system;
  const auto& d = *ctx.decomposition;
  const ContactLaw<dim> law = make_contact_law<dim>(ctx.contact_law);
  ParticleStore<dim> p = sys.particles;
  p.clear_ghosts();
  double r_max = 0;
  for (std::size_t i = 0; i < p.n_owned(); ++i)
    r_max = std::max(r_max, p.radius[i]);
  // A contact is at most 2 R_max + D0 long; twice that covers the grains' drift since the
  // last migration (less than the neighbour-list skin).
  // The bonds of the order parameters reach kOrderCutoff a.
  const double reach = std::max(2 * (2 * global_max(ctx.world, r_max) + law.interaction_range()),
                                kOrderCutoff * ctx.deck->sample.diameter);
  const Vec<dim> width = Vec<dim>::Constant(reach).cwiseQuotient(sys.cell.length);
  for (int a = 0; a < dim; ++a)
    if (d.narrowest(a) < width[a])
      return std::nullopt; // the same decision on every rank
  Halo<dim> halo;
  halo.borders(p, d, width);
  NetworkFields<dim> f = contact_network(sys.cell, p, contacts, law);
  if (global_sum(ctx.world, f.missing) > 0)
    return std::nullopt;
  rattler_flags(ctx, p, halo, f);
  f.fixed_rattler.assign(p.n_owned(), 0.0);
  for (std::size_t i = 0; i < p.n_owned(); ++i)
    if (std::binary_search(ctx.fixed_rattlers.begin(), ctx.fixed_rattlers.end(), p.id[i]))
      f.fixed_rattler[i] = 1.0;
  strong_flags(ctx, f);
  f.cluster_id.clear();
  for (double id : cluster_ids(p, halo, d, f.pairs))
    f.cluster_id.push_back(std::int64_t(id));
  order_flags(ctx, p, halo, f);
  halo.reverse_values(f.contacts, d);
  halo.reverse_values(f.carrying_contacts, d);
  halo.reverse_values(f.mean_stress, d);
  for (auto& c : f.net_force)
    halo.reverse_values(c, d);
  for (auto& c : f.net_moment)
    halo.reverse_values(c, d);
  for (auto& c : f.stress)
    halo.reverse_values(c, d);
  const std::size_t n = p.n_owned();
  f.contacts.resize(n);
  f.carrying_contacts.resize(n);
  f.mean_stress.resize(n);
  for (auto& c : f.net_force)
    c.resize(n);
  for (auto& c : f.net_moment)
    c.resize(n);
  for (auto& c : f.stress)
    c.resize(n);
  return f;
}

template std::optional<NetworkFields<2>> network_fields<2>(const RunContext<2>&,
                                                           const ContactStore<2>&);
template std::optional<NetworkFields<3>> network_fields<3>(const RunContext<3>&,
                                                           const ContactStore<3>&);

} // namespace granpack
