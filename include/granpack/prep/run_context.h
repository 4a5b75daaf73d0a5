#pragma once
// What a stage works on: the distributed state, the deck, the current material (a `set`
// stage changes it), the log and the output directory. Stages orchestrate; physics lives in
// the kernels and communication in comm/.
#include <mpi.h>

#include <filesystem>
#include <memory>
#include <vector>

#include "granpack/comm/decomposition.h"
#include "granpack/core/system.h"
#include "granpack/io/deck.h"
#include "granpack/io/log.h"
#include "granpack/io/report.h"

namespace granpack {

template <int dim> struct RunContext {
  MPI_Comm world = MPI_COMM_WORLD;
  const Deck* deck = nullptr;
  MaterialSpec material;  ///< current material (starts as the deck's)
  System<dim> system;
  /// Created by the stage that builds the sample, once the cell is known.
  std::unique_ptr<Decomposition<dim>> decomposition;
  Log* log = nullptr;
  std::filesystem::path output_dir;
  int stage_index = -1;
  std::string stage_name;
  /// The stresses and fixed axes of the last compress stage (pressure_steps scales them,
  /// fix_rattlers takes its force scale from them); empty before any compress stage.
  std::vector<double> stress;
  std::vector<bool> fixed;
  double pressure = 0;

  /// Solid fraction: sum of grain volumes (areas in 2D) over the cell's. Collective.
  double solid_fraction() const;
};

}  // namespace granpack
