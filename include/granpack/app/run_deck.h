#pragma once
// `granpack run`: validates the deck, runs its stages in order, writes final.h5, report.json
// and log.txt into the output directory.
#include <mpi.h>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "granpack/io/deck.h"

namespace granpack {

struct RunOptions {
  std::filesystem::path deck;
  std::filesystem::path output_dir; ///< empty: out/<deck stem>
  std::optional<std::filesystem::path> restart;
  /// Restart: let the stages after the one in progress differ from the checkpoint's deck.
  bool allow_deck_change = false;
  /// Override the deck's [output] checkpoint_every_steps / checkpoint_every_seconds.
  std::optional<std::int64_t> checkpoint_every_steps;
  std::optional<double> checkpoint_every_seconds;
  bool quiet = false;
  /// Run the deck with this seed instead of its own (docs/deck.md, "Seeds").
  std::optional<std::uint64_t> seed;
  /// Put before every terminal line of the run (an ensemble's "[sample 3] ").
  std::string terminal_prefix;
};

/// Collective on world. Returns the process exit code; throws granpack::Error on failure.
int run_deck(MPI_Comm world, const RunOptions& options);

/// The deck, read on rank 0 and broadcast (every rank validates the same bytes and throws
/// the same InputError); with `seed`, reseeded as `run --seed` does. Collective on world.
Deck load_deck_collectively(MPI_Comm world, const std::filesystem::path& path,
                            std::optional<std::uint64_t> seed);

/// `granpack check`: validates decks exactly as `run` does before any work, and that the files
/// their `read` stages name exist, without running anything or writing a file. Returns one
/// summary line per deck (dimension, n, the stages); throws InputError (exit 2) at the first
/// deck that would not start. Collective on world.
std::string check_decks(MPI_Comm world, const std::vector<std::filesystem::path>& decks);

} // namespace granpack
