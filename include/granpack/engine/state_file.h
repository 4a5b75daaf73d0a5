#pragma once
// The run's state to and from configuration files: the writer of every file a run leaves
// (final.h5, write stages, pressure levels, checkpoints, postmortems) and the adoption of a
// configuration read from a file (the read stage and restarts).
#include <array>
#include <filesystem>
#include <string>

#include "granpack/engine/run_context.h"
#include "granpack/io/hdf5_store.h"

namespace granpack {

/// Makes a configuration read from a file the sample: grains, contacts and cell (rate kept),
/// a domain decomposition (the given grid and, if given, its cut planes; else one chosen from
/// the cell's shape) and the grains and contacts moved to their spatial owners. Collective.
/// Used by `read` and restarts.
template <int dim>
void adopt_configuration(RunContext<dim>& ctx, Configuration<dim>&& c,
                         const std::array<int, dim>* grid = nullptr,
                         const std::array<std::vector<double>, dim>* cuts = nullptr);

/// The current state as written into files (owned grains, the contacts, the metadata and, for
/// configurations, the contact network); with a run_state, a checkpoint's. Collective.
template <int dim>
Configuration<dim> state_configuration(const RunContext<dim>& ctx, const std::string& run_state);

/// Writes the current state as an HDF5 configuration file (with its XDMF sidecar); with a
/// run_state (engine/checkpoint.h) the file is a checkpoint.
template <int dim>
void write_state(RunContext<dim>& ctx, const std::filesystem::path& file,
                 const std::string& run_state = {});

} // namespace granpack
