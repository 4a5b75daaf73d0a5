// `granpack analyze`, motif section: triangles and tetrahedra of the backbone contact network
// per backbone grain ([AR] sec. III D; kernel analysis/network_motifs). The kernel needs the
// contacts between ghosts too, which other ranks own; the elastic normal force depends on the
// overlap only (Walton's rule acts on T), so every rank rebuilds its local backbone edges from
// the geometry: overlapping pairs whose N^e(h) exceeds the force threshold, neither grain a
// rattler. On the contacts a rank owns this reproduces the file's N^e (tested: the owned-edge
// count must equal the backbone contact count).
#include "granpack/analysis/network_motifs.h"
#include "granpack/app/analysis_sections.h"
#include "granpack/comm/reduce.h"
#include "granpack/core/error.h"

namespace granpack {

template <int dim> nlohmann::json analyze_motifs(const PackingView<dim>& v) {
  const auto& p = v.particles();
  const ContactLaw<dim>& law = v.law;
  MotifGraph g;
  g.id = p.id;
  g.owned.assign(p.size(), 0);
  for (std::size_t i = 0; i < p.n_owned(); ++i)
    g.owned[i] = 1;
  // Every local pair in contact: sweep owned and ghost grains alike (a cell list over all).
  CellGrid<dim> grid;
  double rmax = 0;
  for (double r : p.radius)
    rmax = std::max(rmax, r);
  grid.build(p, v.system.cell, 2 * rmax * (1 + 1e-9));
  std::int64_t owned_edges = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (v.rattler(i))
      continue;
    const Vec<dim> ri = v.system.cell.to_real(p.position[i]);
    grid.for_each_neighbor_cell(grid.cell_of_particle(i), [&](std::size_t c) {
      for (std::size_t k = grid.cell_start(c); k < grid.cell_start(c + 1); ++k) {
        const std::size_t j = grid.order()[k];
        if (j <= i || p.id[j] == p.id[i] || v.rattler(j))
          continue;
        const double dist = (grid.sorted_position(k) - ri).norm();
        const double h = p.radius[i] + p.radius[j] - dist;
        if (h <= 0)
          continue;
        const double r_eff = p.radius[i] * p.radius[j] / (p.radius[i] + p.radius[j]);
        if (normal_response(law.normal, h, r_eff).force <= v.force_threshold)
          continue;
        g.edges.emplace_back(i, j);
        // Edges counted once globally: at the owner of the smaller id (the contact owner).
        const std::size_t first = p.id[i] < p.id[j] ? i : j;
        owned_edges += first < p.n_owned();
      }
    });
  }
  owned_edges = global_sum(v.world, owned_edges);
  GRANPACK_CHECK(owned_edges == v.backbone.metrics.backbone_contacts,
                 "motifs: " << owned_edges << " backbone contacts rebuilt from the geometry, "
                            << v.backbone.metrics.backbone_contacts
                            << " in the file: the file's forces do not match its geometry");
  NetworkMotifs m = count_network_motifs(g);
  global_sum_in_place(v.world, m.sums.sums());
  const MotifStatistics s = finish_network_motifs(m.sums);
  return {{"triangles", s.triangles},
          {"tetrahedra", s.tetrahedra},
          {"triangles_per_grain", s.triangles_per_grain},
          {"tetrahedra_per_grain", s.tetrahedra_per_grain},
          {"fraction_in_triangle", s.fraction_in_triangle},
          {"fraction_in_tetrahedron", s.fraction_in_tetrahedron},
          {"triangle_pairs_sharing_edge", s.triangle_pairs_sharing_edge},
          {"tetrahedron_pairs_sharing_face", s.tetrahedron_pairs_sharing_face},
          {"consistent", s.consistent}};
}

template nlohmann::json analyze_motifs<2>(const PackingView<2>&);
template nlohmann::json analyze_motifs<3>(const PackingView<3>&);

} // namespace granpack
