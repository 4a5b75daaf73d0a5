#pragma once
// The parallel HDF5 store: configurations and checkpoints, one file written collectively by all
// ranks (each rank writes its own slice; nothing is gathered to rank 0) and read back on any
// rank count. Schema, units and an h5py example: docs/hdf5-schema.md.
//
// Writes are atomic: the file is written as "<path>.tmp" and renamed to `path` by rank 0 only
// after every rank has closed it, so a crash or a failed write never destroys a previous file
// of that name. A sidecar "<stem>.xdmf" (ParaView/VisIt) is written after the rename.
#include <mpi.h>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "granpack/analysis/contact_network.h"
#include "granpack/core/cell.h"
#include "granpack/core/contact_store.h"
#include "granpack/core/error.h"
#include "granpack/core/particles.h"
#include "granpack/io/state_parameters.h"

namespace granpack {

/// Version of the schema written by this code (root attribute "format_version").
inline constexpr int kHdf5FormatVersion = 1;

/// Root attributes of a granpack HDF5 file, plus the deck text and the parameters in force.
struct FileMeta {
  std::string granpack_version; ///< empty on write: this build's version
  int dimension = 0;            ///< on write: taken from the template parameter
  std::int64_t n_particles = 0; ///< on write: computed (sum of owned particles over ranks)
  std::int64_t n_contacts = 0;  ///< on write: computed (sum of owned contacts over ranks)
  double time = 0;              ///< simulated time (s)
  std::int64_t step = 0;        ///< time-step counter
  int stage_index = 0;          ///< index of the preparation stage in the deck (0-based)
  std::string stage_name;
  std::string deck_text;              ///< the deck the run was started from, verbatim
  std::string kind = "configuration"; ///< "configuration" | "checkpoint"
  /// Checkpoints only: the run's state beyond the grains (stage, stage-internal state,
  /// completed stage reports) as JSON text (docs/long-jobs.md); empty otherwise.
  std::string run_state;
  /// The group /parameters: the contact law and stress target that produced the state. Absent
  /// from files written before it existed (their readers replay the deck: state_parameters.h).
  std::optional<StateParameters> parameters;
};

/// What one rank writes or reads: the cell, its particles (owned only; ghosts are never
/// stored) and its contacts (each contact on exactly one rank).
template <int dim> struct Configuration {
  Cell<dim> cell;
  ParticleStore<dim> particles;
  ContactStore<dim> contacts;
  FileMeta meta;
  /// Written as /network (docs/hdf5-schema.md) when set (on every rank or none): per contact
  /// in the order of `contacts`, per grain in the owned order of `particles`. Not read back
  /// (but for the fixed_rattler column: read_fixed_rattlers).
  std::optional<NetworkFields<dim>> network;
};

/// Collective on comm. Every rank writes its owned particles and its contacts as one
/// contiguous slice (offsets by MPI_Exscan). Throws the same Error on every rank if the
/// configuration is inconsistent (duplicate-free ids are not checked; negative ids, contact
/// keys with first >= second, a kind other than configuration/checkpoint are) or if the file
/// cannot be written; in that case `path` is left as it was and no temp file remains.
template <int dim>
void write_configuration(MPI_Comm comm, const std::filesystem::path& path,
                         const Configuration<dim>& c);

/// Collective on comm; any rank count, whatever count wrote the file. With P ranks and n
/// particles in the file, rank r gets particles [n*r/P, n*(r+1)/P) in file order, contacts
/// likewise (the comm layer redistributes them to their spatial owners). Throws InputError on
/// every rank, naming the file and the problem, for a missing, non-HDF5, truncated or
/// inconsistent file, a missing dataset/attribute, or a dimension other than dim.
template <int dim>
Configuration<dim> read_configuration(MPI_Comm comm, const std::filesystem::path& path);

/// Collective on comm, like read_configuration: the ids (sorted, on every rank) of the grains
/// that the file's /network/fixed_rattler flags, the rattlers that the writing run's last
/// fix_rattlers stage placed (RunContext::fixed_rattlers), for a `read` stage to keep them;
/// empty when the file has no such dataset (checkpoints: their /run_state holds the list;
/// files written before it existed). Throws InputError like read_configuration, also for a
/// flag other than 0 or 1.
std::vector<std::int64_t> read_fixed_rattlers(MPI_Comm comm, const std::filesystem::path& path);

/// Collective on comm (cheap: root attributes, /deck, /run_state and /parameters; may be called
/// with MPI_COMM_SELF on one rank). Used to dispatch on the dimension before read_configuration.
/// Throws InputError like read_configuration.
FileMeta read_file_meta(MPI_Comm comm, const std::filesystem::path& path);

/// One snapshot of a trajectory file (docs/hdf5-schema.md, "Trajectories").
struct TrajectorySnapshot {
  std::string group; ///< "/snapshots/<step, 12 digits>"
  std::int64_t step = 0;
  double time = 0;
  std::int64_t n_particles = 0;
  std::int64_t n_contacts = 0;
  bool network = false; ///< the snapshot has its /network group
};

/// The group of the snapshot of `step` in a trajectory file.
std::string snapshot_group(std::int64_t step);

/// Collective on comm. Appends `c` (whose meta.deck_text should be empty: the deck is stored
/// once, at the root) as the group snapshot_group(c.meta.step) of the trajectory at `path`,
/// creating the file (root attributes kind = "trajectory", dimension, /deck = deck_text) if it
/// does not exist. Not atomic: a crash during the append may leave the file unreadable. Throws
/// WriteError on every rank naming the file and the step, also if that step is already there.
template <int dim>
void append_snapshot(MPI_Comm comm, const std::filesystem::path& path, const Configuration<dim>& c,
                     const std::string& deck_text);

/// Collective on comm (rank 0 reads serially; the file must be closed). The trajectory's
/// snapshots in step order, on rank 0 (empty elsewhere). Throws Error naming the file.
std::vector<TrajectorySnapshot> read_trajectory_index(MPI_Comm comm,
                                                      const std::filesystem::path& path);

/// Collective on comm (rank 0 writes serially). Deletes the snapshots after `after_step`
/// (written by a run interrupted after its last checkpoint); nothing if the file is absent.
void prune_trajectory(MPI_Comm comm, const std::filesystem::path& path, std::int64_t after_step);

/// Collective on comm, like read_file_meta. Human-readable summary for `granpack info`:
/// kind, dimension, particles, contacts, cell lengths and rates, time, step, stage, version.
std::string describe_file(MPI_Comm comm, const std::filesystem::path& path);

/// True after a failed write left an HDF5 file open on this rank (on every rank: write failures
/// are collective). HDF5 1.10.8 cannot close it and segfaults when its shutdown at
/// MPI_Finalize tries: the process must end without MPI_Finalize (drivers/main.cpp).
bool hdf5_file_left_open();

namespace detail {
/// Test hook: if set, write_configuration calls it on every rank at named points of the write
/// ("after_particles", "before_rename"); throwing from it simulates a failure there.
void set_hdf5_write_hook(std::function<void(std::string_view stage)> hook);
} // namespace detail

extern template void write_configuration<2>(MPI_Comm, const std::filesystem::path&,
                                            const Configuration<2>&);
extern template void write_configuration<3>(MPI_Comm, const std::filesystem::path&,
                                            const Configuration<3>&);
extern template Configuration<2> read_configuration<2>(MPI_Comm, const std::filesystem::path&);
extern template Configuration<3> read_configuration<3>(MPI_Comm, const std::filesystem::path&);
extern template void append_snapshot<2>(MPI_Comm, const std::filesystem::path&,
                                        const Configuration<2>&, const std::string&);
extern template void append_snapshot<3>(MPI_Comm, const std::filesystem::path&,
                                        const Configuration<3>&, const std::string&);

} // namespace granpack
