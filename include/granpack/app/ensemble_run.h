#pragma once
// `granpack run DECK --samples K`: K independent samples of one deck side by side in one MPI
// job. The ranks are split into groups of `ranks_per_sample`; each group runs its samples one
// after the other on its own communicator, sample S (seed S) in OUT/sample_S/, exactly as
// `granpack run DECK --seed S -o OUT/sample_S` on that many ranks would (same files).
#include <mpi.h>

#include <cstdint>
#include <filesystem>

#include "granpack/app/run_deck.h"

namespace granpack {

struct EnsembleOptions {
  /// The deck, OUT (output_dir), checkpoint overrides and quiet; seed/restart are per sample.
  RunOptions run;
  int samples = 1;
  std::uint64_t first_seed = 1; ///< samples are seeds first_seed .. first_seed + samples - 1
  int ranks_per_sample = 0;     ///< 0: size / samples if that divides, else 1
  /// Resume: skip the samples that finished (report.json), continue those with a checkpoint,
  /// start the others.
  bool resume = false;
};

/// The directory of sample `seed` under the ensemble directory.
std::filesystem::path sample_directory(const std::filesystem::path& out, std::uint64_t seed);

/// Collective on world. Returns the exit code: 0 when every sample finished, the first
/// failing sample's code if one failed, 75 if a stop signal interrupted one (its checkpoint
/// is written: --restart resumes). Bad input (deck, options) throws InputError before any run.
int run_ensemble(MPI_Comm world, const EnsembleOptions& options);

} // namespace granpack
