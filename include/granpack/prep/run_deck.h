#pragma once
// `granpack run`: validates the deck, runs its stages in order, writes final.h5, report.json
// and log.txt into the output directory.
#include <mpi.h>

#include <filesystem>
#include <optional>

namespace granpack {

struct RunOptions {
  std::filesystem::path deck;
  std::filesystem::path output_dir;  ///< empty: out/<deck stem>
  std::optional<std::filesystem::path> restart;
  bool quiet = false;
};

/// Collective on world. Returns the process exit code; throws granpack::Error on failure.
int run_deck(MPI_Comm world, const RunOptions& options);

}  // namespace granpack
