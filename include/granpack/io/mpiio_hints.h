#pragma once
// MPI-IO hints for the parallel HDF5 files, from the environment (docs/long-jobs.md,
// "Several nodes"):
//
//   GRANPACK_MPIIO_HINTS="romio_cb_write=enable,cb_nodes=8,striping_factor=16"
//
// Each key=value pair becomes an MPI_Info entry of every file granpack opens with MPI-IO
// (HDF5 hands them to MPI_File_open). On a parallel file system the collective-buffering
// hints (cb_nodes: how many aggregator ranks write; cb_buffer_size) and the Lustre striping
// ones (striping_factor, striping_unit; on a new file only) decide whether a checkpoint of
// 10^7 grains takes seconds or minutes. Unknown keys are ignored by MPI, as the standard says.
#include <mpi.h>

#include <string>
#include <utility>
#include <vector>

namespace granpack {

/// The pairs of a hints string ("k=v,k=v"; commas, semicolons or blanks separate them).
/// Throws InputError naming the variable and the bad entry.
std::vector<std::pair<std::string, std::string>> parse_mpiio_hints(const std::string& text);

/// Checks GRANPACK_MPIIO_HINTS at start-up (before any file is written), so a typo stops the
/// job at once with exit 2 rather than at its first checkpoint.
void check_mpiio_hints();

/// A new MPI_Info with the hints of GRANPACK_MPIIO_HINTS (MPI_INFO_NULL when unset or empty);
/// the caller frees it with MPI_Info_free unless it is MPI_INFO_NULL.
MPI_Info mpiio_hints_info();

} // namespace granpack
