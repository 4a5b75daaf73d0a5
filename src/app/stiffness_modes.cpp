#include "granpack/app/stiffness_modes.h"

#ifdef GRANPACK_HAVE_RIGIDITY

#include <array>
#include <map>
#include <nlohmann/json.hpp>

#include "granpack/analysis/rigidity_blocks.h"
#include "granpack/comm/broadcast.h"
#include "granpack/comm/communicator.h"
#include "granpack/comm/gather.h"
#include "granpack/core/error.h"
#include "granpack/io/json_hdf5.h"
#include "granpack/io/xdmf.h"
#include "granpack/rigidity/mechanisms.h"

namespace granpack {

namespace {
/// The file's content (docs/stiffness.md "Modes as fields"): every grain of the packing, the
/// grains off the backbone (rattlers) at rest in every mode.
template <int dim>
nlohmann::json modes_document(const PackingView<dim>& v, const StiffnessSystem<dim>& s,
                              const SoftModes& m, const std::vector<Particle<dim>>& grains) {
  const int g = s.grain_dofs();
  constexpr int rd = dim == 2 ? 1 : 3;
  nlohmann::json doc;
  doc["kind"] = "stiffness_modes";
  doc["dimension"] = dim;
  doc["mean_kn"] = s.mean_kn;
  doc["rotation_length"] = s.layout.ell;
  doc["rotations"] = s.layout.rotations;
  const Vec<dim>& length = v.system.cell.length;
  doc["cell_length"] = std::vector<double>(length.data(), length.data() + dim);
  // The divalent grains' free rollings (s.divalent: two records per grain, every rank's).
  std::map<GlobalId, std::array<double, 6>> rolling;
  nlohmann::json div_grain = nlohmann::json::array(), neighbours = div_grain, points = div_grain;
  for (std::size_t k = 0; k + 1 < s.divalent.size(); k += 2) {
    const DivalentContact &c1 = s.divalent[k], &c2 = s.divalent[k + 1];
    const Vec<3> p1(c1.branch[0], c1.branch[1], c1.branch[2]),
        p2(c2.branch[0], c2.branch[1], c2.branch[2]);
    const Eigen::Matrix<double, 6, 1> x = divalent_rolling_mode(p1, p2, s.layout.ell);
    // The unknowns are (u, rho = theta * ell): the file holds u and theta (rad).
    rolling[c1.grain] = {
        x[0], x[1], x[2], x[3] / s.layout.ell, x[4] / s.layout.ell, x[5] / s.layout.ell};
    div_grain.push_back(c1.grain);
    neighbours.push_back({c1.neighbour, c2.neighbour});
    points.push_back({p1[0], p1[1], p1[2], p2[0], p2[1], p2[2]});
  }
  nlohmann::json id = nlohmann::json::array(), position = id, radius = id, backbone = id,
                 divalent = id, rolling_u = id, rolling_theta = id;
  for (const auto& p : grains) {
    id.push_back(p.id);
    const Vec<dim> x = v.system.cell.to_real(Cell<dim>::wrap(p.position));
    position.push_back(std::vector<double>(x.data(), x.data() + dim));
    radius.push_back(p.radius);
    backbone.push_back(s.numbering.index.count(p.id) ? 1 : 0);
    const auto r = rolling.find(p.id);
    divalent.push_back(r == rolling.end() ? 0 : 1);
    const std::array<double, 6> x6 = r == rolling.end() ? std::array<double, 6>{} : r->second;
    rolling_u.push_back({x6[0], x6[1], x6[2]});
    rolling_theta.push_back({x6[3], x6[4], x6[5]});
  }
  doc["grains"] = {{"id", id},
                   {"position", position},
                   {"radius", radius},
                   {"backbone", backbone},
                   {"divalent", divalent}};
  if (!rolling.empty())
    doc["divalent"] = {{"grain", div_grain},
                       {"neighbours", neighbours},
                       {"contact_points", points},
                       {"rolling", {{"displacement", rolling_u}, {"rotation", rolling_theta}}}};
  nlohmann::json modes;
  modes["eigenvalue_over_mean_kn"] = m.eigenvalues;
  for (std::size_t k = 0; k < m.values.size(); ++k) {
    nlohmann::json u = nlohmann::json::array(), rot = u;
    for (const auto& p : grains) {
      const auto it = s.numbering.index.find(p.id);
      const double* x = it == s.numbering.index.end()
                            ? nullptr
                            : m.values[k].data() + std::size_t(it->second) * std::size_t(g);
      std::vector<double> t(dim, 0.0), r(rd, 0.0);
      for (int a = 0; x && a < dim; ++a)
        t[std::size_t(a)] = x[a];
      // The unknowns are rho = theta * ell (rigidity_blocks.h): the file holds theta (rad).
      for (int a = 0; x && s.layout.rotations && a < rd; ++a)
        r[std::size_t(a)] = x[dim + a] / s.layout.ell;
      u.push_back(t);
      if (rd == 1)
        rot.push_back(r[0]);
      else
        rot.push_back(r);
    }
    nlohmann::json one = {{"displacement", u}, {"eigenvalue_over_mean_kn", m.eigenvalues[k]}};
    if (s.layout.rotations)
      one["rotation"] = rot;
    modes[std::to_string(k)] = one;
  }
  doc["modes"] = modes;
  return doc;
}
} // namespace

template <int dim>
void write_stiffness_modes(const PackingView<dim>& v, StiffnessSystem<dim>& s,
                           const DirectSolver& k1, int count, const std::filesystem::path& path) {
  const SoftModes m = softest_modes(s.k1.uu, k1, s.numbering, s.grain_dofs(), count, s.mean_kn);
  const std::vector<Particle<dim>> grains = gather_particles(v.particles(), v.world);
  std::string error;
  if (rank_of(v.world) == 0) {
    try {
      write_json_as_hdf5(path, modes_document(v, s, m, grains));
      write_modes_xdmf(xdmf_path_for(path), path.filename().string(), dim,
                       std::int64_t(grains.size()), int(m.values.size()), s.layout.rotations,
                       !s.divalent.empty());
    } catch (const std::exception& e) {
      error = e.what();
    }
  }
  broadcast_string(v.world, error); // known on rank 0 only: every rank throws it
  if (!error.empty())
    throw WriteError(error);
}

template void write_stiffness_modes<2>(const PackingView<2>&, StiffnessSystem<2>&,
                                       const DirectSolver&, int, const std::filesystem::path&);
template void write_stiffness_modes<3>(const PackingView<3>&, StiffnessSystem<3>&,
                                       const DirectSolver&, int, const std::filesystem::path&);

} // namespace granpack

#endif // GRANPACK_HAVE_RIGIDITY
