#pragma once
// `granpack analyze FILE.h5`: the packing's characterisation after [AR] (docs/analysis.md),
// computed on any rank count from a configuration file. Collective on world.
#include <mpi.h>

#include <filesystem>
#include <optional>
#include <string>

#include "granpack/app/analysis_sections.h"
#include "granpack/contact/derived_constants.h"

namespace granpack {

struct AnalyzeOptions {
  std::filesystem::path file;
  std::optional<std::filesystem::path> json; ///< also write the results here
  /// also write them as HDF5 (curves and histograms as datasets; io/json_hdf5.h)
  std::optional<std::filesystem::path> hdf5;
  /// Force-carrying threshold as a fraction of a^2 P (a^(dim-1) P in 2D), P the measured
  /// pressure: the [AR] equilibrium tolerance, below which forces are not resolved.
  double threshold = kCarryingThreshold;
  PairOptions pairs;       ///< g(r) range and bin
  DensityOptions density;  ///< 2D density fluctuations and holes
  bool print_table = true; ///< rank 0 prints the table (not when an ensemble analyses many files)
};

/// Returns the JSON text of the results (on every rank); rank 0 prints the table.
std::string analyze_file(MPI_Comm world, const AnalyzeOptions& options);

} // namespace granpack
