#pragma once
// report.json: the machine-readable record of a run (schema in docs/report.md).
// Keys never change name once released; later features add keys.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace granpack {

/// One stage's entry. Empty optionals are written as null ("not applicable").
struct StageReport {
  std::string name, kind;
  std::int64_t steps = 0;        ///< time steps taken by the stage
  double time = 0;               ///< simulated time spent in the stage, s
  std::optional<bool> equilibrated;
  std::optional<double> phi, pressure, kappa, inertia_max, z, z_star, x0;
  double wall_seconds = 0;
};

struct RunReport {
  std::string version;
  int dimension = 3;
  std::int64_t n = 0;
  int ranks = 1;
  std::string deck;   ///< path of the deck as given
  std::vector<StageReport> stages;
  std::string final_file;  ///< relative to the output directory
  double wall_seconds = 0;
};

/// The JSON text of a report (2-space indent).
std::string to_json(const RunReport& r);
/// Writes path atomically (temporary name, then rename). Call on one rank.
void write_report(const std::filesystem::path& path, const RunReport& r);
/// Writes text to path atomically: a crash never leaves a half-written file under that name.
void write_text_atomically(const std::filesystem::path& path, const std::string& text);

}  // namespace granpack
