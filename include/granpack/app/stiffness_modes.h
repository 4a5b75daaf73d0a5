#pragma once
// `granpack stiffness --modes K --modes-file OUT.h5`: the K softest modes of the stiffened
// K(1) (the eigenpairs whose eigenvalues `--eigenvalues` reports: what is left once the
// trivial, divalent and pivoting mechanisms are removed, so an unexpected mechanism comes
// first) as per-grain displacement and rotation fields, with an XDMF sidecar for ParaView's
// Warp By Vector (docs/stiffness.md); and the divalent grains' free rollings, which the modes
// leave out, as one more field (each grain's `divalent_rolling_mode`, the others at rest), with
// the grains, their partners and contact points, and the cell's lengths. Collective on v.world.
#include <filesystem>

#include "granpack/packing/packing_view.h"
#include "granpack/rigidity/direct_solver.h"
#include "granpack/rigidity/stiffness_system.h"

namespace granpack {

/// `k1`: the factors of s.k1.uu. Writes `path` (and its sidecar) from rank 0; an error there is
/// thrown on every rank.
template <int dim>
void write_stiffness_modes(const PackingView<dim>& v, StiffnessSystem<dim>& s,
                           const DirectSolver& k1, int count, const std::filesystem::path& path);

extern template void write_stiffness_modes<2>(const PackingView<2>&, StiffnessSystem<2>&,
                                              const DirectSolver&, int,
                                              const std::filesystem::path&);
extern template void write_stiffness_modes<3>(const PackingView<3>&, StiffnessSystem<3>&,
                                              const DirectSolver&, int,
                                              const std::filesystem::path&);

} // namespace granpack
