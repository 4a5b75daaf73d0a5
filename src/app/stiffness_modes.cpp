#include "granpack/app/stiffness_modes.h"

#ifdef GRANPACK_HAVE_RIGIDITY

#include <nlohmann/json.hpp>

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
  nlohmann::json id = nlohmann::json::array(), position = id, radius = id, backbone = id;
  for (const auto& p : grains) {
    id.push_back(p.id);
    const Vec<dim> x = v.system.cell.to_real(Cell<dim>::wrap(p.position));
    position.push_back(std::vector<double>(x.data(), x.data() + dim));
    radius.push_back(p.radius);
    backbone.push_back(s.numbering.index.count(p.id) ? 1 : 0);
  }
  doc["grains"] = {{"id", id}, {"position", position}, {"radius", radius}, {"backbone", backbone}};
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
                       std::int64_t(grains.size()), int(m.values.size()), s.layout.rotations);
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
