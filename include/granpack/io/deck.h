#pragma once
// The deck: a TOML file declaring the sample, the material, the numerics, the output and an
// ordered list of stages. parse_deck() validates everything before any work is done; every
// key is documented in docs/deck.md (units SI).
#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "granpack/io/stage_params.h"

namespace granpack {

struct SampleSpec {
  int dimension = 3;
  std::int64_t n = 0;
  double diameter = 0;                       ///< a: the (largest) grain diameter, m
  std::string distribution = "monodisperse"; ///< or "uniform": d uniform in [ratio a, a]
  double min_diameter_ratio = 0.5;
  std::uint64_t seed = 1;
  friend bool operator==(const SampleSpec&, const SampleSpec&) = default;
};

struct MaterialSpec {
  double density = 0;                    ///< kg/m^3 (2D: per unit thickness, kg/m^3 x 1 m)
  std::string normal_law = "hertz";      ///< "hertz" or "linear"
  double young_modulus = 0;              ///< E, Pa (hertz)
  double poisson_ratio = 0;              ///< nu (hertz; also sets K_T/K_N)
  double normal_stiffness = 0;           ///< K_N, N/m (linear)
  double tangential_stiffness_ratio = 0; ///< K_T/K_N (linear; hertz uses (2-2nu)/(2-nu))
  double friction = 0;                   ///< mu, may be inf
  double damping = 0;                    ///< zeta, fraction of critical damping
  bool damping_tension = true;           ///< N^e + N^v may pull (false: N^v >= -N^e)
  bool walton_rescaling = true;          ///< [AR] App. A (hertz); false only for experiments
  // [GRC] parts, off when 0 (2D forces are per unit thickness, as every 2D force here).
  double cohesion_force = 0;    ///< F0, N: maximum attraction (eq. 4-5)
  double cohesion_range = 0;    ///< D0, m: range of the attraction
  double rolling_stiffness = 0; ///< K_r, N m / rad (eq. 9)
  double rolling_friction = 0;  ///< mu_r, m: |moment| <= mu_r N^e (eq. 10), inf allowed
  double rolling_damping = 0;   ///< zeta_r, fraction of critical rolling damping (not [GRC])
  friend bool operator==(const MaterialSpec&, const MaterialSpec&) = default;
};

struct NumericsSpec {
  double time_step_fraction = 0.02; ///< dt / (contact duration of the stiffest contact)
  double skin = 0.1;                ///< Verlet skin, fraction of the largest diameter
  /// Largest overlap h / min(R_i, R_j) before an MD stage stops with a diagnosis.
  double max_overlap = 0.1;
  /// Move the domain cut planes to balance the grain counts (comm/rebalance.h) when the
  /// largest rank holds more than load_balance_threshold times the mean.
  bool load_balance = false;
  double load_balance_threshold = 1.1;
  /// How the halo's forward and reverse exchanges reach other ranks: "messages" (MPI messages)
  /// or "shared_memory" (an MPI-3 shared-memory window, when every rank is on one node;
  /// messages otherwise). The same results bit for bit; only the time differs: the default
  /// since the benchmark of 2026-12-07 (docs/performance.md, "The shared-memory halo").
  std::string halo = "shared_memory";
  friend bool operator==(const NumericsSpec&, const NumericsSpec&) = default;
};

struct OutputSpec {
  std::int64_t log_every = 1000; ///< steps between progress lines
  bool quiet = false;
  std::int64_t checkpoint_every_steps = 0;  ///< 0: off
  double checkpoint_every_seconds = 3600.0; ///< wall seconds; 0: off
  /// MD steps between the snapshots of OUT/trajectory.h5 (engine/trajectory.h); 0: off
  std::int64_t trajectory_every = 0;
  /// Simulated seconds between snapshots: one after each MD step that crosses a multiple of
  /// it (engine/trajectory.h); 0: off
  double trajectory_every_time = 0;
  /// A snapshot at the end of every stage (engine/trajectory.h)
  bool trajectory_stage_ends = false;
  /// Any of the three trajectory keys is on.
  bool trajectory() const {
    return trajectory_every > 0 || trajectory_every_time > 0 || trajectory_stage_ends;
  }
  friend bool operator==(const OutputSpec&, const OutputSpec&) = default;
};

struct StageSpec {
  int index = 0;    ///< 0-based position in the deck
  std::string kind; ///< one of stage_kinds()
  std::string name; ///< user label (defaults to kind)
  StageParams params;
  friend bool operator==(const StageSpec&, const StageSpec&) = default;
};

struct Deck {
  std::string file; ///< as given by the user, for messages
  std::string text; ///< the deck's full text (stored in every output file)
  SampleSpec sample;
  MaterialSpec material;
  NumericsSpec numerics;
  OutputSpec output;
  std::vector<StageSpec> stages;
};

/// Parses and validates a deck. Throws InputError (exit code 2) naming the file, the key with
/// its table path and line, the value and what is allowed. Does no I/O: under MPI the caller
/// reads the file on one rank and broadcasts its text, so every rank validates identically.
Deck parse_deck(const std::string& text, const std::string& file_name);

/// The text of a deck file; a missing or unreadable file is an InputError.
std::string read_deck_text(const std::filesystem::path& path);

/// Reads the file and parses it.
Deck load_deck(const std::filesystem::path& path);

} // namespace granpack
