#pragma once
// The XDMF sidecar of a granpack HDF5 file: a small XML text that tells ParaView/VisIt how to
// map /particles/* onto a point cloud (Polyvertex topology), so the .h5 opens as particles,
// and, in files with a /network group, the contact network as line cells coloured by force
// (docs/visualisation.md).
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace granpack {

/// What the sidecar needs to know about the HDF5 file it describes.
struct XdmfParticles {
  std::string h5_name; ///< the .h5 file, relative to the sidecar's directory
  int dimension = 3;   ///< 2 -> geometry "XY", 3 -> "XYZ"
  std::int64_t n_particles = 0;
  double time = 0; ///< the grids' time value (a trajectory's sidecar puts the step here)
  /// Contacts drawn from /network (its datasets and the per-grain ones); -1: no /network.
  std::int64_t n_network_contacts = -1;
  /// The HDF5 group holding the configuration's groups: "" (the file's root) or, in a
  /// trajectory, "/snapshots/<step>".
  std::string group;
};

/// The sidecar's name for an HDF5 file: same directory and stem, extension ".xdmf".
std::filesystem::path xdmf_path_for(const std::filesystem::path& h5_path);

/// XDMF 3 text: a grid "particles" (geometry /particles/position, attributes radius, id,
/// velocity, angular_velocity; with /network also contacts, carrying_contacts, net_force,
/// net_moment, mean_stress, ...) and,
/// with /network and contacts, a grid "contacts" (Polyline cells of 2 points /network/point,
/// connectivity /network/line; cell attributes normal_force, tangential_force, kind), both in
/// one spatial collection.
std::string particles_xdmf(const XdmfParticles& p);

/// XDMF 3 text of a trajectory (docs/visualisation.md): one temporal collection whose members
/// are the grids particles_xdmf() writes for each snapshot (`frames`, in time order, each with
/// its group), all in the file h5_name; ParaView's "XDMF Reader" plays it as a time series.
std::string trajectory_xdmf(const std::string& h5_name, const std::vector<XdmfParticles>& frames);

/// Not collective (call on one rank). Writes trajectory_xdmf() to `xdmf_path` atomically.
void write_trajectory_xdmf(const std::filesystem::path& xdmf_path, const std::string& h5_name,
                           const std::vector<XdmfParticles>& frames);

/// Not collective (call on one rank). Writes particles_xdmf(p) to `xdmf_path` atomically
/// (temp + rename, see atomic_file.h). Throws Error naming the file.
void write_particles_xdmf(const std::filesystem::path& xdmf_path, const XdmfParticles& p);

/// Not collective (call on one rank). Writes the sidecar of a `granpack stiffness --modes`
/// file (docs/stiffness.md): one grid "grains" (geometry /grains/position; radius, id,
/// backbone, divalent) with, per mode k < `modes`, the node attributes mode_k (vector
/// /modes/k/displacement) and, with `rotations`, mode_k_rotation (/modes/k/rotation: a vector
/// in 3D, a scalar in 2D), for ParaView's Warp By Vector; with `divalent_rolling` (3D) the
/// divalent grains' free rollings divalent_rolling and divalent_rolling_rotation (vectors,
/// /divalent/rolling/displacement and rotation).
void write_modes_xdmf(const std::filesystem::path& xdmf_path, const std::string& h5_name,
                      int dimension, std::int64_t n_grains, int modes, bool rotations,
                      bool divalent_rolling = false);

} // namespace granpack
