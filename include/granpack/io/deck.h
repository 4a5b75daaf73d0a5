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

#include "granpack/dynamics/equilibrium.h"

namespace granpack {

struct SampleSpec {
  int dimension = 3;
  std::int64_t n = 0;
  double diameter = 0;  ///< a: the (largest) grain diameter, m
  std::string distribution = "monodisperse";  ///< or "uniform": d uniform in [ratio a, a]
  double min_diameter_ratio = 0.5;
  std::uint64_t seed = 1;
  friend bool operator==(const SampleSpec&, const SampleSpec&) = default;
};

struct MaterialSpec {
  double density = 0;                 ///< kg/m^3 (2D: per unit thickness, kg/m^3 x 1 m)
  std::string normal_law = "hertz";   ///< "hertz" or "linear"
  double young_modulus = 0;           ///< E, Pa (hertz)
  double poisson_ratio = 0;           ///< nu (hertz; also sets K_T/K_N)
  double normal_stiffness = 0;        ///< K_N, N/m (linear)
  double tangential_stiffness_ratio = 0;  ///< K_T/K_N (linear; hertz uses (2-2nu)/(2-nu))
  double friction = 0;                ///< mu, may be inf
  double damping = 0;                 ///< zeta, fraction of critical damping
  // [GRC] parts, off when 0 (2D forces are per unit thickness, as every 2D force here).
  double cohesion_force = 0;          ///< F0, N: maximum attraction (eq. 4-5)
  double cohesion_range = 0;          ///< D0, m: range of the attraction
  double rolling_stiffness = 0;       ///< K_r, N m / rad (eq. 9)
  double rolling_friction = 0;        ///< mu_r, m: |moment| <= mu_r N^e (eq. 10), inf allowed
  double rolling_damping = 0;         ///< zeta_r, fraction of critical rolling damping (not [GRC])
  friend bool operator==(const MaterialSpec&, const MaterialSpec&) = default;
};

struct NumericsSpec {
  double time_step_fraction = 0.02;  ///< dt / (contact duration of the stiffest contact)
  double skin = 0.1;                 ///< Verlet skin, fraction of the largest diameter
  /// Largest overlap h / min(R_i, R_j) before an MD stage stops with a diagnosis.
  double max_overlap = 0.1;
  friend bool operator==(const NumericsSpec&, const NumericsSpec&) = default;
};

struct OutputSpec {
  std::int64_t log_every = 1000;  ///< steps between progress lines
  bool quiet = false;
  std::int64_t checkpoint_every_steps = 0;   ///< 0: off
  double checkpoint_every_seconds = 3600.0;  ///< wall seconds; 0: off
  friend bool operator==(const OutputSpec&, const OutputSpec&) = default;
};


struct LatticeStage {
  std::string lattice;  ///< "fcc" (3D) or "hex" (2D triangular)
  double phi = 0;       ///< solid fraction of the lattice
  std::vector<std::int64_t> cells;  ///< unit cells per axis (n = 4 prod in fcc, 2 prod in hex)
  friend bool operator==(const LatticeStage&, const LatticeStage&) = default;
};
struct RandomStage {
  double phi = 0;  ///< solid fraction of the non-overlapping random placement
  std::string placement = "relax";  ///< "relax" (overlap removal) or "sequential" (RSA)
  friend bool operator==(const RandomStage&, const RandomStage&) = default;
};
struct CompressStage {
  double pressure = 0;                  ///< Pa: mean of the prescribed stresses (scales, kappa)
  std::vector<double> stress;           ///< prescribed Sigma_a per axis, Pa (dim entries)
  std::vector<bool> fixed;              ///< axes kept at constant length (dim entries)
  std::optional<double> inertia_max;    ///< cap on I = eps_dot sqrt(m/(aP)), eq. (23)
  std::optional<double> strain_rate_max;  ///< cap on |dL/dt| / L, 1/s ([GRC] method 2: 0.05/T0)
  double cell_mass = 1.0;               ///< M / (sum of grain masses)
  /// [GRC] eq. 3 form: M = cell_mass x (sum of grain masses) x a / L0, L0 the mean cell
  /// length at the stage start (M = 0.3 sum m / L in the paper's units of a).
  bool cell_mass_per_length = false;
  std::int64_t max_steps = 0;           ///< 0: no limit
  /// Steps between velocity quenches once the force and stress criteria hold but the kinetic
  /// one does not (0: never). [AR] sec. III checks stability by zeroing the velocities.
  std::int64_t quench_interval = 0;
  /// Quench every interval whatever the state, the cell's rate too (quench_when = "always"):
  /// drains a floppy packing whose cell breathes on its mechanisms with nothing to damp it.
  /// The criteria are then judged only half an interval or more after a quench.
  bool quench_always = false;
  EquilibriumTolerances tolerance;  ///< [AR] sec. III criteria
  friend bool operator==(const CompressStage&, const CompressStage&) = default;
};
struct SetStage {
  std::optional<double> friction, damping;
  friend bool operator==(const SetStage&, const SetStage&) = default;
};
struct WriteStage {
  std::string file;  ///< relative to the output directory
  friend bool operator==(const WriteStage&, const WriteStage&) = default;
};
/// Starts from a configuration file written by granpack (grains, contacts, cell).
struct ReadStage {
  std::string file;  ///< path as given (relative to the working directory)
  friend bool operator==(const ReadStage&, const ReadStage&) = default;
};
/// Event-driven hard-sphere gas at fixed volume ([AR] sec. III melting, sec. IV B mixing).
struct EdGasStage {
  double collisions_per_grain = 0;  ///< n_coll: stop after n_coll * n collisions
  std::uint64_t seed = 0;           ///< Maxwell velocity draw
  friend bool operator==(const EdGasStage&, const EdGasStage&) = default;
};
/// Lubachevsky-Stillinger growth to a solid fraction ([AR] A' samples).
struct LsCompressStage {
  double phi = 0;              ///< target solid fraction
  double growth_rate = 1e-2;   ///< d(diameter)/dt in units of the rms velocity
  double rescale_every = 1.0;  ///< collisions per grain between kinetic-energy resets
  std::vector<double> report_phi = {0.49, 0.58};  ///< collisions per grain counted between these
  std::uint64_t seed = 0;
  friend bool operator==(const LsCompressStage&, const LsCompressStage&) = default;
};
/// Homothetic expansion of the cell and the grain centres by a factor lambda ([AR] C).
struct ExpandStage {
  double factor = 1;
  friend bool operator==(const ExpandStage&, const ExpandStage&) = default;
};
/// Quasistatic compression: `count` compress stages at P_k = P_0 factor^k, k = 1..count, P_0
/// the pressure of the previous compress stage; each level is equilibrated and recorded.
struct PressureStepsStage {
  double factor = 0;
  std::int64_t count = 0;
  bool write = true;       ///< write each equilibrated level to <name>_<k>.h5
  CompressStage compress;  ///< controls (inertia_max, cell_mass, max_steps, tolerances)
  friend bool operator==(const PressureStepsStage&, const PressureStepsStage&) = default;
};
/// Treatment II of [AR] sec. III C: backbone frozen, rattlers pushed by small random forces
/// onto it (frictionless) until they rest in equilibrium.
struct FixRattlersStage {
  double force = 1e-2;       ///< push magnitude / (a^2 P) (2D: a P)
  double tolerance = 1e-3;   ///< equilibrium: net force on every rattler < tolerance x push
  std::int64_t max_steps = 0;
  std::uint64_t seed = 0;
  std::optional<double> pressure;  ///< P for the push scale (default: the last compress's)
  friend bool operator==(const FixRattlersStage&, const FixRattlersStage&) = default;
};

/// [GRC] method 2, first step: Maxwell velocities of rms V0 in a fixed cell, MD with the
/// cohesive law until every grain belongs to one cluster and the packing is in equilibrium.
struct AggregateStage {
  double velocity_ratio = 0;         ///< V0 / V*, V* = sqrt(F0 D0 / m) ([GRC] eq. 7)
  std::uint64_t seed = 0;
  std::int64_t max_steps = 0;        ///< 0: no limit
  std::int64_t cluster_every = 10000;  ///< steps between cluster counts (progress)
  /// Once all grains form one cluster, steps between velocity quenches (0: never): drains
  /// the slow undamped motions of the floppy aggregate (a deviation from [GRC], docs/deck.md).
  std::int64_t quench_interval = 0;
  /// Steps from the first single cluster to the first quench: the aggregate's floppy parts
  /// first fold freely and close their loops, as in [GRC]; the quenches then only drain.
  std::int64_t quench_delay = 0;
  EquilibriumTolerances tolerance;   ///< force, moment, kinetic (the cell is fixed)
  friend bool operator==(const AggregateStage&, const AggregateStage&) = default;
};

/// [GRC] series B: the normal stiffness (and the rolling stiffness with it) ramped
/// geometrically to a target under stress control; a compress stage then equilibrates.
struct StiffenStage {
  double normal_stiffness = 0;       ///< target K_N, N/m (linear law)
  std::int64_t steps = 0;            ///< time steps of the whole ramp
  std::int64_t increments = 100;     ///< equal factors of the geometric ramp
  bool scale_rolling = true;         ///< K_r follows K_N ([GRC] table I: K_r = 1e-4 a^2 K_N)
  CompressStage control;             ///< prescribed stress, fixed axes, cell mass, rate caps
  friend bool operator==(const StiffenStage&, const StiffenStage&) = default;
};

using StageParams = std::variant<LatticeStage, RandomStage, CompressStage, SetStage, WriteStage,
                                 EdGasStage, LsCompressStage, ExpandStage, PressureStepsStage,
                                 FixRattlersStage, ReadStage, AggregateStage, StiffenStage>;

struct StageSpec {
  int index = 0;     ///< 0-based position in the deck
  std::string kind;  ///< one of stage_kinds()
  std::string name;  ///< user label (defaults to kind)
  StageParams params;
  friend bool operator==(const StageSpec&, const StageSpec&) = default;
};

struct Deck {
  std::string file;  ///< as given by the user, for messages
  std::string text;  ///< the deck's full text (stored in every output file)
  SampleSpec sample;
  MaterialSpec material;
  NumericsSpec numerics;
  OutputSpec output;
  std::vector<StageSpec> stages;
};

/// Every stage kind the deck language knows, in documentation order.
const std::vector<std::string>& stage_kinds();

/// Parses and validates a deck. Throws InputError (exit code 2) naming the file, the key with
/// its table path and line, the value and what is allowed. Does no I/O: under MPI the caller
/// reads the file on one rank and broadcasts its text, so every rank validates identically.
Deck parse_deck(const std::string& text, const std::string& file_name);

/// The text of a deck file; a missing or unreadable file is an InputError.
std::string read_deck_text(const std::filesystem::path& path);

/// Reads the file and parses it.
Deck load_deck(const std::filesystem::path& path);

}  // namespace granpack
