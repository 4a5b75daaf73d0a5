#pragma once
// `granpack stiffness FILE.h5`: is the packing rigid, where are its mechanisms, how
// hyperstatic and how stiff is it ([AR] sec. II C, III B, IV D; docs/stiffness.md).
// Distributed (PETSc/SLEPc, METIS); collective on world.
#include <mpi.h>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "granpack/contact/derived_constants.h"

namespace granpack {

/// How the moduli are computed (docs/stiffness.md, "Moduli of large packings"): a sparse
/// factorisation (which also counts the mechanisms), Krylov solves with an algebraic
/// multigrid (the moduli only), or the first up to `krylov_above` grain unknowns.
enum class StiffnessSolver { kDirect, kKrylov, kAuto };

struct StiffnessOptions {
  std::filesystem::path file;
  std::optional<std::filesystem::path> json; ///< also write the results here
  /// Force-carrying threshold / (a^(dim-1) P), as in `granpack analyze`.
  double threshold = kCarryingThreshold;
  /// MUMPS null-pivot threshold, relative to the matrix's infinity norm (CNTL(3)).
  double null_pivot_threshold = 1e-12;
  /// Smallest eigenvalues of the stiffened grain block to report (SLEPc).
  int eigenvalues = 6;
  /// With modes > 0: the `modes` softest modes of the stiffened K(1) as per-grain fields in
  /// this HDF5 file and its XDMF sidecar (app/stiffness_modes.h).
  int modes = 0;
  std::optional<std::filesystem::path> modes_file;
  StiffnessSolver solver = StiffnessSolver::kAuto;
  /// `auto` takes the Krylov path above this many grain unknowns (g n*): the direct path's
  /// largest measured case, D at n = 32 000, has 172 000 and takes 3.6 GB per rank.
  std::int64_t krylov_above = 300000;
  /// Relative true residual of each Krylov solve; the condensation's error is of order
  /// rtol^2 cond(K) (rigidity/condensation.h).
  double krylov_rtol = 1e-8;
  int krylov_max_iterations = 20000;
};

/// Returns the JSON text of the results (on every rank); rank 0 prints the table.
std::string stiffness_file(MPI_Comm world, const StiffnessOptions& options);

} // namespace granpack
