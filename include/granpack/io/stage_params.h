#pragma once
// The stage kinds of the deck language (docs/deck.md): each kind's parameters, read from its
// [[stage]] table by its static parse(), and StageParams at the end of this file, the registry
// of all kinds. The stages' runners live above, in stages/ (run_stage, stages/stages.h): the
// parameters are here, in io/, because the deck, checkpoints and old files' replay read them.
//
// A stage kind is a struct with
//   static constexpr std::string_view kind = "...";  // its name in `kind = "..."`
//   static X parse(StageTable& t);  // reads the table's keys (src/io/stage_params.cpp); the
//                                   // table's unknown keys are refused after it returns
//   an optional `std::uint64_t seed` member: `run --seed` shifts it (io/deck_seed.h)
//   operator== (a restart compares the stages of two decks)
// and one line in StageParams; its runner is run_stage(RunContext<dim>&, const X&)
// (stages/stages.h, defined in the stage's file). docs/ARCHITECTURE.md, "How to add a stage".
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "granpack/dynamics/equilibrium.h"

namespace granpack {

/// What a kind's parse() reads: its table and the deck around it (io/stage_table.h).
struct StageTable;

struct LatticeStage {
  static constexpr std::string_view kind = "lattice";
  static LatticeStage parse(StageTable& t);
  std::string lattice;             ///< "fcc" (3D) or "hex" (2D triangular)
  double phi = 0;                  ///< solid fraction of the lattice
  std::vector<std::int64_t> cells; ///< unit cells per axis (n = 4 prod in fcc, 2 prod in hex)
  friend bool operator==(const LatticeStage&, const LatticeStage&) = default;
};
struct RandomStage {
  static constexpr std::string_view kind = "random";
  static RandomStage parse(StageTable& t);
  double phi = 0;                  ///< solid fraction of the non-overlapping random placement
  std::string placement = "relax"; ///< "relax" (overlap removal) or "sequential" (RSA)
  friend bool operator==(const RandomStage&, const RandomStage&) = default;
};
struct CompressStage {
  static constexpr std::string_view kind = "compress";
  static CompressStage parse(StageTable& t);
  double pressure = 0;                   ///< Pa: mean of the prescribed stresses (scales, kappa)
  std::vector<double> stress;            ///< prescribed Sigma_a per axis, Pa (dim entries)
  std::vector<bool> fixed;               ///< axes kept at constant length (dim entries)
  std::optional<double> inertia_max;     ///< cap on I = eps_dot sqrt(m/(aP)), eq. (23)
  std::optional<double> strain_rate_max; ///< cap on |dL/dt| / L, 1/s ([GRC] method 2: 0.05/T0)
  double cell_mass = 1.0;                ///< M / (sum of grain masses)
  /// [GRC] eq. 3 form: M = cell_mass x (sum of grain masses) x a / L0, L0 the mean cell
  /// length at the stage start (M = 0.3 sum m / L in the paper's units of a).
  bool cell_mass_per_length = false;
  std::int64_t max_steps = 0; ///< 0: no limit
  /// Steps between velocity quenches once the force and stress criteria hold but the kinetic
  /// one does not (0: never). [AR] sec. III checks stability by zeroing the velocities.
  std::int64_t quench_interval = 0;
  /// Quench every interval whatever the state, the cell's rate too (quench_when = "always"):
  /// drains a floppy packing whose cell breathes on its mechanisms with nothing to damp it.
  /// The criteria are then judged only half an interval or more after a quench.
  bool quench_always = false;
  EquilibriumTolerances tolerance; ///< [AR] sec. III criteria
  friend bool operator==(const CompressStage&, const CompressStage&) = default;
};
struct SetStage {
  static constexpr std::string_view kind = "set";
  static SetStage parse(StageTable& t);
  std::optional<double> friction, damping;
  /// Rolling damping zeta_r from here on (needs the deck's rolling_stiffness > 0): e.g. an
  /// aggregation without it, as [GRC]'s model, and the equilibration stages with it.
  std::optional<double> rolling_damping;
  friend bool operator==(const SetStage&, const SetStage&) = default;
};
struct WriteStage {
  static constexpr std::string_view kind = "write";
  static WriteStage parse(StageTable& t);
  std::string file; ///< relative to the output directory
  friend bool operator==(const WriteStage&, const WriteStage&) = default;
};
/// Starts from a configuration file written by granpack (grains, contacts, cell).
struct ReadStage {
  static constexpr std::string_view kind = "read";
  static ReadStage parse(StageTable& t);
  std::string file; ///< path as given (relative to the working directory)
  friend bool operator==(const ReadStage&, const ReadStage&) = default;
};
/// Event-driven hard-sphere gas at fixed volume ([AR] sec. III melting, sec. IV B mixing).
struct EdGasStage {
  static constexpr std::string_view kind = "ed_gas";
  static EdGasStage parse(StageTable& t);
  double collisions_per_grain = 0; ///< n_coll: stop after n_coll * n collisions
  std::uint64_t seed = 0;          ///< Maxwell velocity draw
  friend bool operator==(const EdGasStage&, const EdGasStage&) = default;
};
/// Lubachevsky-Stillinger growth to a solid fraction ([AR] A' samples).
struct LsCompressStage {
  static constexpr std::string_view kind = "ls_compress";
  static LsCompressStage parse(StageTable& t);
  double phi = 0;             ///< target solid fraction
  double growth_rate = 1e-2;  ///< d(diameter)/dt in units of the rms velocity
  double rescale_every = 1.0; ///< collisions per grain between kinetic-energy resets
  std::vector<double> report_phi = {0.49, 0.58}; ///< collisions per grain counted between these
  std::uint64_t seed = 0;
  friend bool operator==(const LsCompressStage&, const LsCompressStage&) = default;
};
/// Homothetic expansion of the cell and the grain centres by a factor lambda ([AR] C).
struct ExpandStage {
  static constexpr std::string_view kind = "expand";
  static ExpandStage parse(StageTable& t);
  double factor = 1;
  friend bool operator==(const ExpandStage&, const ExpandStage&) = default;
};
/// Quasistatic compression: `count` compress stages at P_k = P_0 factor^k, k = 1..count, P_0
/// the pressure of the previous compress stage; each level is equilibrated and recorded.
struct PressureStepsStage {
  static constexpr std::string_view kind = "pressure_steps";
  static PressureStepsStage parse(StageTable& t);
  double factor = 0;
  std::int64_t count = 0;
  bool write = true;      ///< write each equilibrated level to <name>_<k>.h5
  CompressStage compress; ///< controls (inertia_max, cell_mass, max_steps, tolerances)
  friend bool operator==(const PressureStepsStage&, const PressureStepsStage&) = default;
};
/// Treatment II of [AR] sec. III C: backbone frozen, rattlers pushed by small random forces
/// onto it (frictionless) until they rest in equilibrium.
struct FixRattlersStage {
  static constexpr std::string_view kind = "fix_rattlers";
  static FixRattlersStage parse(StageTable& t);
  double force = 1e-2;     ///< push magnitude / (a^2 P) (2D: a P)
  double tolerance = 1e-3; ///< equilibrium: net force on every rattler < tolerance x push
  std::int64_t max_steps = 0;
  std::uint64_t seed = 0;
  std::optional<double> pressure; ///< P for the push scale (default: the last compress's)
  friend bool operator==(const FixRattlersStage&, const FixRattlersStage&) = default;
};

/// [GRC] method 2, first step: Maxwell velocities of rms V0 in a fixed cell, MD with the
/// cohesive law until every grain belongs to one cluster and the packing is in equilibrium.
struct AggregateStage {
  static constexpr std::string_view kind = "aggregate";
  static AggregateStage parse(StageTable& t);
  double velocity_ratio = 0; ///< V0 / V*, V* = sqrt(F0 D0 / m) ([GRC] eq. 7)
  std::uint64_t seed = 0;
  std::int64_t max_steps = 0;         ///< 0: no limit
  std::int64_t cluster_every = 10000; ///< steps between cluster counts (progress)
  /// Once all grains form one cluster, steps between velocity quenches (0: never): drains
  /// the slow undamped motions of the floppy aggregate (a deviation from [GRC], docs/deck.md).
  std::int64_t quench_interval = 0;
  /// Steps from the first single cluster to the first quench: the aggregate's floppy parts
  /// first fold freely and close their loops, as in [GRC]; the quenches then only drain.
  std::int64_t quench_delay = 0;
  EquilibriumTolerances tolerance; ///< force, moment, kinetic (the cell is fixed)
  friend bool operator==(const AggregateStage&, const AggregateStage&) = default;
};

/// [GRC] series B: the normal stiffness (and the rolling stiffness with it) ramped
/// geometrically to a target under stress control; a compress stage then equilibrates.
struct StiffenStage {
  static constexpr std::string_view kind = "stiffen";
  static StiffenStage parse(StageTable& t);
  double normal_stiffness = 0;   ///< target K_N, N/m (linear law)
  std::int64_t steps = 0;        ///< time steps of the whole ramp
  std::int64_t increments = 100; ///< equal factors of the geometric ramp
  bool scale_rolling = true;     ///< K_r follows K_N ([GRC] table I: K_r = 1e-4 a^2 K_N)
  CompressStage control;         ///< prescribed stress, fixed axes, cell mass, rate caps
  friend bool operator==(const StiffenStage&, const StiffenStage&) = default;
};

/// [AR] App. E: one divalent grain (two backbone contacts, 3D with friction) launched along its
/// free rolling (eqs. E1-E2), then MD under the constant stress, optionally with the contact
/// network frozen; records the trajectory and says whether the network holds
/// (docs/stiffness.md, "Is a divalent grain's free rolling stable?").
struct DivalentLaunchStage {
  static constexpr std::string_view kind = "divalent_launch";
  static DivalentLaunchStage parse(StageTable& t);
  std::int64_t pick = 0;       ///< 0: the divalent grain with the largest contact force, 1: next
  bool frozen_network = false; ///< only the pairs in contact at launch may interact
  double centrifugal_ratio = 1e-4; ///< m omega0^2 D / |F| ([AR]: 1e-4)
  double turns = 1;                ///< run until the centre has turned this many times (at omega0)
  std::int64_t max_steps = 0;      ///< 0: from turns
  std::int64_t record_every = 500; ///< steps between trajectory rows
  /// Collapse: more than this fraction of the contacts in place at launch have opened.
  double collapse_fraction = 0.5;
  /// Rearrangement: the kinetic energy exceeds this multiple of the launch energy.
  double energy_factor = 10;
  /// When the run stops before its turns: "collapse" (default), "rearrangement" (the first of
  /// a rearrangement or a collapse: the network is failing) or "never".
  std::string stop_on = "collapse";
  std::string trajectory = "divalent_trajectory.csv"; ///< relative to the output directory
  CompressStage control; ///< prescribed stress, fixed axes, cell mass (compress's keys)
  friend bool operator==(const DivalentLaunchStage&, const DivalentLaunchStage&) = default;
};

/// The registry of stage kinds, one line each, in documentation order: stage_kinds() lists
/// their names in this order, parse_deck() reads a [[stage]] table with the parse() of the
/// kind it names, `granpack run` calls run_stage() on the parameters.
using StageParams =
    std::variant<LatticeStage, RandomStage, ReadStage, EdGasStage, LsCompressStage, ExpandStage,
                 CompressStage, PressureStepsStage, FixRattlersStage, SetStage, WriteStage,
                 AggregateStage, StiffenStage, DivalentLaunchStage>;

/// Every stage kind the deck language knows, in documentation order (StageParams' order).
const std::vector<std::string>& stage_kinds();

} // namespace granpack
