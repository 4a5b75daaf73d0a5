#include "granpack/packing/packing_view.h"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <numbers>
#include <unordered_map>

#include "granpack/comm/clusters.h"
#include "granpack/comm/communicator.h"
#include "granpack/comm/migration.h"
#include "granpack/comm/reduce.h"
#include "granpack/contact/derived_constants.h"
#include "granpack/core/error.h"

namespace granpack {

template <int dim>
PackingView<dim> load_packing(MPI_Comm world, const std::filesystem::path& file,
                              const FileMeta& meta, double threshold, double reach) {
  PackingView<dim> v;
  v.world = world;
  Configuration<dim> cfg = read_configuration<dim>(world, file);
  v.deck = parse_deck(meta.deck_text, file.string() + ":/deck");
  const StateParameters parameters =
      meta.parameters ? *meta.parameters : replayed_parameters(v.deck, meta.stage_index);
  if (!meta.parameters) {
    const int rank = rank_of(world);
    if (rank == 0)
      std::cerr << "granpack: " << file.string() << " has no /parameters (written by granpack "
                << meta.granpack_version << "): its contact law and stress target are "
                << "replayed from its deck up to stage " << meta.stage_index << "\n";
  }
  v.contact_law = parameters.contact_law;
  v.stress_target = parameters.stress_target;
  v.law = make_contact_law<dim>(v.contact_law);
  v.diameter = v.deck.sample.diameter;

  auto& sys = v.system;
  sys.cell = cfg.cell;
  sys.particles = std::move(cfg.particles);
  sys.contacts = std::move(cfg.contacts);
  v.decomposition = std::make_unique<Decomposition<dim>>(world, sys.cell.length);
  distribute(sys, *v.decomposition);
  auto& p = sys.particles;
  double rmax = 0, volume = 0;
  for (std::size_t i = 0; i < p.n_owned(); ++i) {
    rmax = std::max(rmax, p.radius[i]);
    volume += dim == 3 ? 4.0 / 3.0 * std::numbers::pi * std::pow(p.radius[i], 3)
                       : std::numbers::pi * p.radius[i] * p.radius[i];
  }
  rmax = global_max(world, rmax);
  v.n = global_sum(world, static_cast<std::int64_t>(p.n_owned()));
  v.phi = global_sum(world, volume) / sys.cell.volume();
  // Contacts overlap, so both grains lie within 2 R_max (plus round-off) of each other.
  // The ghost layer cannot be wider than a sub-domain (nearest-neighbour exchange) nor reach
  // half the cell (one image per pair): the requested reach is clipped to that, but never
  // below what the contacts and the local analyses need (1.5 a).
  double limit = 0.5 * sys.cell.length.minCoeff() * (1 - 1e-9);
  for (int k = 0; k < dim; ++k)
    limit = std::min(limit, sys.cell.length[k] / v.decomposition->dims()[k] * (1 - 1e-9));
  const double needed = std::max(1.5 * v.diameter, 2.0 * rmax) * (1 + 1e-9);
  GRANPACK_CHECK(needed <= limit,
                 file.string() << ": the analysis needs grains within " << needed / v.diameter
                               << " a of each sub-domain, more than a sub-domain's width or half "
                                  "the cell: run on fewer ranks");
  v.ghost_width = std::clamp(reach * v.diameter, needed, limit);
  const Vec<dim> width = Vec<dim>::Constant(v.ghost_width).cwiseQuotient(sys.cell.length);
  v.halo.borders(p, *v.decomposition, width);

  // Local index of each contact's two grains: the first is owned (contacts travel with their
  // first grain); of the images of the second, the nearest.
  std::unordered_multimap<GlobalId, std::size_t> where;
  for (std::size_t i = 0; i < p.size(); ++i)
    where.emplace(p.id[i], i);
  std::int64_t lost = 0;
  for (std::size_t k = 0; k < sys.contacts.size(); ++k) {
    const auto& key = sys.contacts.key(k);
    std::size_t i = p.size(), j = p.size();
    for (auto [it, end] = where.equal_range(key.first); it != end; ++it)
      if (it->second < p.n_owned())
        i = it->second;
    double best = std::numeric_limits<double>::infinity();
    if (i < p.size())
      for (auto [it, end] = where.equal_range(key.second); it != end; ++it) {
        const double dist =
            sys.cell.length.cwiseProduct(p.position[it->second] - p.position[i]).norm();
        if (dist < best)
          best = dist, j = it->second;
      }
    if (i == p.size() || j == p.size()) {
      ++lost;
      continue;
    }
    const Vec<dim> r = sys.cell.length.cwiseProduct(p.position[j] - p.position[i]);
    const auto& st = sys.contacts.state(k);
    const bool distant = (st.flags & kDistant) != 0;
    // The law's attraction at the pair's overlap h ([GRC] eq. 4-5: -F0 in contact, -F0 (1 -
    // g/D0) across a gap g = -h; 0 without cohesion). h is computed as -(|r| - R_i - R_j),
    // whose rounding the analyses of the committed files were made with.
    const double attraction = v.law.attraction(-(r.norm() - p.radius[i] - p.radius[j]));
    v.contacts.push_back(
        {i, j, r, st.normal_force, st.tangential_force, attraction, distant, st.rolling});
  }
  GRANPACK_CHECK(global_sum(world, lost) == 0,
                 file.string() << ": " << global_sum(world, lost)
                               << " contacts name grains that are not in contact range");

  // Measured static stress, eq. (8) without the kinetic part; with cohesion N = N^e + N^a.
  Tensor<dim> virial = Tensor<dim>::Zero();
  for (const auto& c : v.contacts)
    virial += (c.total_normal_force() * c.branch.normalized() + c.tangential_force) *
              c.branch.transpose();
  global_sum_in_place(world, std::span<double>(virial.data(), dim * dim));
  v.stress = virial / sys.cell.volume();
  v.pressure = v.stress.trace() / dim;
  // [AR]'s scale a^2 P; with cohesion [GRC]'s F1 = max(F0, a^2 P) (II D), as the engine's
  // criteria: at P* = 0 the pressure is ~0 or negative, and a threshold from it would count
  // distant pairs (N^e = 0) as force-carrying contacts.
  v.force_threshold =
      threshold * force_scale_f1(dim, v.diameter, v.pressure, v.contact_law.cohesion_force);

  for (const auto& c : v.contacts)
    if (c.normal_force > v.force_threshold)
      v.carrying.push_back({c.i, c.j, c.normal_force});
  const int min_contacts = min_backbone_contacts(dim, v.law.friction.mu);
  v.backbone = find_backbone(p, v.halo, *v.decomposition, v.carrying, min_contacts);
  // Backbone coordinations on the ghosts too (the force statistics split by coordination).
  v.halo.forward_values(v.backbone.counts, *v.decomposition);
  return v;
}

template <int dim> void select_interaction_network(PackingView<dim>& v) {
  const auto& p = v.particles();
  std::vector<std::pair<GlobalId, GlobalId>> pairs;
  for (const auto& c : v.contacts)
    pairs.emplace_back(p.id[c.i], p.id[c.j]);
  const ClusterSplit split = split_clusters(pairs, v.world);
  v.detached_clusters = split.other_clusters;
  v.detached_grains = split.other_grains;
  auto in_largest = [&](std::size_t i) {
    return std::binary_search(split.largest.begin(), split.largest.end(), p.id[i]);
  };
  // find_backbone with one contact required: every grain of the largest cluster stays, the rest
  // (no pair left) are flagged.
  v.carrying.clear();
  for (const auto& c : v.contacts)
    if (in_largest(c.i))
      v.carrying.push_back({c.i, c.j, c.normal_force});
  v.backbone = find_backbone(v.particles(), v.halo, *v.decomposition, v.carrying, 1);
  v.halo.forward_values(v.backbone.counts, *v.decomposition);
  v.interaction_network = true;
}

template void select_interaction_network<2>(PackingView<2>&);
template void select_interaction_network<3>(PackingView<3>&);
template PackingView<2> load_packing<2>(MPI_Comm, const std::filesystem::path&, const FileMeta&,
                                        double, double);
template PackingView<3> load_packing<3>(MPI_Comm, const std::filesystem::path&, const FileMeta&,
                                        double, double);

} // namespace granpack
