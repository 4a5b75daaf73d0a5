#pragma once
// `granpack stiffness FILE.h5`: is the packing rigid, where are its mechanisms, how
// hyperstatic and how stiff is it ([AR] sec. II C, III B, IV D; docs/stiffness.md).
// Distributed (PETSc/SLEPc, METIS); collective on world.
#include <mpi.h>

#include <filesystem>
#include <optional>
#include <string>

#include "granpack/contact/derived_constants.h"

namespace granpack {

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
};

/// Returns the JSON text of the results (on every rank); rank 0 prints the table.
std::string stiffness_file(MPI_Comm world, const StiffnessOptions& options);

} // namespace granpack
