#pragma once
// The XDMF sidecar of a granpack HDF5 file: a small XML text that tells ParaView/VisIt how to
// map /particles/* onto a point cloud (Polyvertex topology), so the .h5 opens as particles.
#include <cstdint>
#include <filesystem>
#include <string>

namespace granpack {

/// What the sidecar needs to know about the HDF5 file it describes.
struct XdmfParticles {
  std::string h5_name; ///< the .h5 file, relative to the sidecar's directory
  int dimension = 3;   ///< 2 -> geometry "XY", 3 -> "XYZ"
  std::int64_t n_particles = 0;
  double time = 0;
};

/// The sidecar's name for an HDF5 file: same directory and stem, extension ".xdmf".
std::filesystem::path xdmf_path_for(const std::filesystem::path& h5_path);

/// XDMF 3 text: geometry /particles/position, attributes radius, id, velocity.
std::string particles_xdmf(const XdmfParticles& p);

/// Not collective (call on one rank). Writes particles_xdmf(p) to `xdmf_path` atomically
/// (temp + rename, see atomic_file.h). Throws Error naming the file.
void write_particles_xdmf(const std::filesystem::path& xdmf_path, const XdmfParticles& p);

} // namespace granpack
