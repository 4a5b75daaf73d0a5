#pragma once
// The moduli of `granpack stiffness` by iterative solves, for packings whose sparse
// factorisation does not fit (docs/stiffness.md, "Moduli of large packings"): one Krylov
// solve per strain of the cell on the backbone's grain block, the trivial translations
// pinned and the divalent and pivoting modes stiffened as on the direct path
// (remove_known_mechanisms), the strains condensed from the approximate solutions
// (condense_approximately). Without a factorisation nothing counts the unexpected mechanisms
// or the inertia: the JSON says which quantities are not computed. Collective.
#include <nlohmann/json.hpp>

#include "granpack/rigidity/condensation.h"

namespace granpack {

template <int dim> struct KrylovModuli {
  Moduli<dim> k1; ///< K(1) alone, no Omega term (`constitutive`)
  Moduli<dim> k;  ///< K(1) + K(2) with the Omega term
  bool converged = true;
  /// Per matrix: method, preconditioner, iterations and true residuals of every solve
  /// (forward, then adjoint), setup and solve seconds, and why a solve stopped short.
  nlohmann::json report;
};

/// `stress`: the Cauchy stress of the Omega term (as for the direct path's K condensation).
template <int dim>
KrylovModuli<dim> krylov_moduli(const PackingView<dim>& v, const StiffnessSystem<dim>& s,
                                const VoigtVec<dim>& stress, double rtol, int max_iterations);

} // namespace granpack
