#pragma once
// report.json: the machine-readable record of a run (schema in docs/report.md).
// Keys never change name once released; later features add keys.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace granpack {

/// One stage's entry. Empty optionals are written as null ("not applicable").
/// Wall seconds of a stage's MD steps by phase (engine/step_timers.h), mean over the ranks,
/// and the force phase of the slowest rank in wall and in CPU time: the load balance
/// (docs/performance.md). Measured over the part of the stage this run executed (after a
/// restart: since the restart).
struct PhaseSeconds {
  double forces = 0, neighbor = 0, comm = 0, integrate = 0;
  double forces_slowest = 0;                     ///< max over ranks of the force phase's wall time
  double forces_cpu = 0, forces_cpu_slowest = 0; ///< CPU time: mean and max over ranks
  /// The slowest rank's force work over the mean (1: balanced).
  double force_imbalance() const { return forces_cpu > 0 ? forces_cpu_slowest / forces_cpu : 1.0; }
};

/// A stage's wall time by part, mean over the ranks (engine/step_timers.h StageTimers): the
/// four MD phases (as in PhaseSeconds), files written and read, the event-driven engine, and
/// the rest, `other` = wall_seconds - the parts (set-up, analysis of the state, logging,
/// equilibrium tests, waiting at the stage's start and end), so that the parts add up to
/// wall_seconds.
struct WallSplit {
  double forces = 0, neighbor = 0, comm = 0, integrate = 0, io = 0, event_driven = 0, other = 0;
  double listed() const { return forces + neighbor + comm + integrate + io + event_driven; }
};

/// MD steps of one class (dense or loose by contacts per grain): steps, grain-steps, the wall
/// seconds of their phases (mean over the ranks) and the rate (none without seconds).
struct StepClass {
  std::int64_t steps = 0, particle_steps = 0;
  double seconds = 0;
  std::optional<double> rate() const {
    return seconds > 0 ? std::optional<double>(static_cast<double>(particle_steps) / seconds)
                       : std::nullopt;
  }
};
struct StepClasses {
  double threshold = 0; ///< a step is dense with at least this many contacts per grain
  StepClass dense, loose;
};

struct StageReport {
  std::string name, kind;
  std::int64_t steps = 0; ///< time steps taken by the stage
  double time = 0;        ///< simulated time spent in the stage, s
  std::optional<bool> equilibrated;
  std::optional<double> phi, pressure, kappa, inertia_max, z, z_star, x0;
  std::optional<double> x2; ///< fraction of grains with exactly 2 backbone contacts
  std::optional<double> z2; ///< Z(2) = <N^2>/<N>^2 over backbone contacts (eq. 27)
  /// Stage-specific numbers (e.g. collisions per grain of an event-driven stage), in order.
  std::vector<std::pair<std::string, double>> values;
  /// Sub-entries (one per pressure level of pressure_steps), same schema.
  std::vector<StageReport> levels;
  double wall_seconds = 0;
  std::optional<PhaseSeconds> phase_seconds; ///< stages with MD steps
  std::optional<WallSplit> wall_split;       ///< every stage (absent in files before it)
  std::optional<StepClasses> md_classes;     ///< stages with MD steps

  /// Copies the state of the packing (pressure, kappa, z, z*, x0, x2, Z(2)) from another entry.
  void copy_state_metrics(const StageReport& from) {
    pressure = from.pressure;
    kappa = from.kappa;
    z = from.z;
    z_star = from.z_star;
    x0 = from.x0;
    x2 = from.x2;
    z2 = from.z2;
  }
};

struct RunReport {
  std::string version;
  std::string build_commit; ///< the source commit of the binary (app/build_info.h)
  bool build_dirty = false; ///< built from a tree with uncommitted changes
  int dimension = 3;
  std::int64_t n = 0;
  int ranks = 1;
  std::string deck; ///< path of the deck as given
  std::vector<StageReport> stages;
  std::string final_file; ///< relative to the output directory
  double wall_seconds = 0;
};

/// One stage entry as JSON text (the report.json schema) and back: checkpoints carry the
/// entries of the completed stages so that a restarted run's report.json is whole.
std::string stage_report_json(const StageReport& s);
StageReport stage_report_from_json(const std::string& text);

/// The JSON text of a report (2-space indent).
std::string to_json(const RunReport& r);
/// Writes path atomically (temporary name, then rename). Call on one rank.
void write_report(const std::filesystem::path& path, const RunReport& r);
/// Writes text to path atomically: a crash never leaves a half-written file under that name.
void write_text_atomically(const std::filesystem::path& path, const std::string& text);

} // namespace granpack
