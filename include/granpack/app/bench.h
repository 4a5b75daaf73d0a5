#pragma once
// `granpack bench`: the engine benchmark of docs/performance.md. Builds the reference problem
// (glass spheres in a dense periodic packing read from a granpack file, optionally replicated
// kx x ky x kz times), times a fixed-volume MD run and reports particle-steps/s per rank,
// memory per grain and the time breakdown; optionally exports the same state for LAMMPS
// (jobs/bench/lammps/) and the static forces for the cross-check.
#include <mpi.h>

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "granpack/io/deck.h"

namespace granpack {

struct BenchOptions {
  std::filesystem::path file;            ///< 3D packing written by granpack (e.g. A_n4000)
  std::array<int, 3> replicate{1, 1, 1}; ///< periodic copies per axis
  std::int64_t steps = 1000;             ///< timed MD steps
  double velocity_rms = 1e-3;            ///< m/s per component, Gaussian, seeded by grain id
  std::uint64_t seed = 1;
  double pressure = 1e4;            ///< P of the packing (Pa), for the report only
  double time_step_fraction = 0.02; ///< dt = fraction x contact time at the typical overlap
  double skin = 0.1;                ///< Verlet skin / a
  /// The halo's transport ([numerics] halo): "messages" or "shared_memory"; the deck's default.
  std::string halo = NumericsSpec{}.halo;
  std::optional<std::filesystem::path> lammps_data;   ///< write the initial state here
  std::optional<std::filesystem::path> static_forces; ///< per-grain static forces (text)
  std::optional<std::filesystem::path> json;          ///< results as one JSON object
};

/// Collective on world. Returns the human-readable report (rank 0; empty elsewhere).
std::string run_bench(MPI_Comm world, const BenchOptions& options);

} // namespace granpack
