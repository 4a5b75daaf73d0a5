#include "granpack/io/xdmf.h"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include "granpack/core/error.h"
#include "granpack/io/atomic_file.h"

namespace granpack {

namespace {
/// Escapes the characters XML forbids in text (a file name may contain '&' or '<').
std::string xml_escape(const std::string& s) {
  std::string out;
  for (char ch : s) {
    switch (ch) {
    case '&':
      out += "&amp;";
      break;
    case '<':
      out += "&lt;";
      break;
    case '>':
      out += "&gt;";
      break;
    case '"':
      out += "&quot;";
      break;
    default:
      out += ch;
    }
  }
  return out;
}
} // namespace

std::filesystem::path xdmf_path_for(const std::filesystem::path& h5_path) {
  auto p = h5_path;
  p.replace_extension(".xdmf");
  return p;
}

namespace {
/// The grid(s) of one configuration (a spatial collection of particles and contacts, or the
/// particles alone), indented for a place directly inside <Domain>.
std::string configuration_grid(const XdmfParticles& p) {
  const std::string file = xml_escape(p.h5_name);
  const std::string at = xml_escape(p.group); // "" or "/snapshots/<step>"
  const std::string n = std::to_string(p.n_particles);
  const std::string nd = n + " " + std::to_string(p.dimension);
  const std::string rd = n + " " + (p.dimension == 2 ? "1" : "3");
  const char* geometry = p.dimension == 2 ? "XY" : "XYZ";
  const bool network = p.n_network_contacts >= 0;
  const bool lines = p.n_network_contacts > 0; // ParaView refuses a grid of no cells
  const std::string ind = network ? "  " : ""; // the grids sit inside a collection
  auto item = [&](const std::string& dims, const char* type, const std::string& dataset) {
    return ind + "        <DataItem Dimensions=\"" + dims + "\" NumberType=\"" + type +
           "\" Precision=\"8\" Format=\"HDF\">" + file + ":" + at + dataset + "</DataItem>\n";
  };
  auto attribute = [&](const char* name, const char* kind, const char* center,
                       const std::string& dims, const char* type, const std::string& dataset) {
    return ind + "      <Attribute Name=\"" + name + "\" AttributeType=\"" + kind + "\" Center=\"" +
           center + "\">\n" + item(dims, type, dataset) + ind + "      </Attribute>\n";
  };
  std::ostringstream os;
  os.precision(17);
  if (network)
    os << "    <Grid Name=\"packing\" GridType=\"Collection\" CollectionType=\"Spatial\">\n"
       << "      <Time Value=\"" << p.time << "\"/>\n";
  os << ind << "    <Grid Name=\"particles\" GridType=\"Uniform\">\n"
     << ind << "      <Time Value=\"" << p.time << "\"/>\n"
     << ind << "      <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" << n
     << "\" NodesPerElement=\"1\"/>\n"
     << ind << "      <Geometry GeometryType=\"" << geometry << "\">\n"
     << item(nd, "Float", "/particles/position") << ind << "      </Geometry>\n"
     << attribute("radius", "Scalar", "Node", n, "Float", "/particles/radius")
     << attribute("id", "Scalar", "Node", n, "Int", "/particles/id")
     << attribute("velocity", "Vector", "Node", nd, "Float", "/particles/velocity")
     << attribute("angular_velocity", p.dimension == 2 ? "Scalar" : "Vector", "Node", rd, "Float",
                  "/particles/angular_velocity");
  if (network)
    os << attribute("contacts", "Scalar", "Node", n, "Float", "/network/contacts")
       << attribute("carrying_contacts", "Scalar", "Node", n, "Float", "/network/carrying_contacts")
       << attribute("net_force", "Vector", "Node", nd, "Float", "/network/net_force")
       << attribute("net_moment", p.dimension == 2 ? "Scalar" : "Vector", "Node", rd, "Float",
                    "/network/net_moment")
       << attribute("mean_stress", "Scalar", "Node", n, "Float", "/network/mean_stress")
       // 3D: a Tensor of 9 (ParaView's tensor glyphs, eigenvalues); 2D: 4 components, read by
       // ParaView as a plain 4-component array ("Tensor" insists on 9).
       << attribute("stress", p.dimension == 2 ? "Matrix" : "Tensor", "Node",
                    n + (p.dimension == 2 ? " 4" : " 9"), "Float", "/network/stress")
       << attribute("rattler", "Scalar", "Node", n, "Float", "/network/rattler")
       << attribute("fixed_rattler", "Scalar", "Node", n, "Float", "/network/fixed_rattler")
       << attribute("cluster_id", "Scalar", "Node", n, "Int", "/network/cluster_id")
       << attribute("bond_order", "Scalar", "Node", n, "Float", "/network/bond_order")
       << attribute("crystalline", "Scalar", "Node", n, "Float", "/network/crystalline");
  os << ind << "    </Grid>\n";
  if (lines) {
    const std::string nc = std::to_string(p.n_network_contacts);
    const std::string points =
        std::to_string(2 * p.n_network_contacts) + " " + std::to_string(p.dimension);
    os << "      <Grid Name=\"contacts\" GridType=\"Uniform\">\n"
       << "        <Time Value=\"" << p.time << "\"/>\n"
       << "        <Topology TopologyType=\"Polyline\" NumberOfElements=\"" << nc
       << "\" NodesPerElement=\"2\">\n"
       << item(nc + " 2", "Int", "/network/line") << "        </Topology>\n"
       << "        <Geometry GeometryType=\"" << geometry << "\">\n"
       << item(points, "Float", "/network/point") << "        </Geometry>\n"
       << attribute("normal_force", "Scalar", "Cell", nc, "Float", "/network/normal_force")
       << attribute("tangential_force", "Scalar", "Cell", nc, "Float", "/network/tangential_force")
       << attribute("kind", "Scalar", "Cell", nc, "Int", "/network/kind")
       << attribute("mobilisation", "Scalar", "Cell", nc, "Float", "/network/mobilisation")
       << attribute("strong", "Scalar", "Cell", nc, "Float", "/network/strong")
       << "      </Grid>\n";
  }
  if (network)
    os << "    </Grid>\n";
  return os.str();
}

std::string xdmf_header(const std::string& what, const std::string& h5_name) {
  return "<?xml version=\"1.0\" ?>\n<!-- granpack " + what + "; data in " + xml_escape(h5_name) +
         " (see docs/hdf5-schema.md, docs/visualisation.md) -->\n<Xdmf Version=\"3.0\">\n"
         "  <Domain>\n";
}

const char* const kXdmfFooter = "  </Domain>\n</Xdmf>\n";

/// Writes `text` to `path` atomically (temp + rename); throws WriteError naming the file.
void write_text_atomically(const std::filesystem::path& path, const std::string& text) {
  const auto temp = temp_path_for(path);
  {
    errno = 0;
    std::ofstream out(temp, std::ios::binary | std::ios::trunc);
    out << text;
    out.close();
    if (!out) {
      const int e = errno; // set by the failed write or close (ENOSPC, EDQUOT, EFBIG)
      std::error_code ec;
      std::filesystem::remove(temp, ec);
      throw WriteError("cannot write " + path.string() + ": " +
                       (e ? std::strerror(e) : "write failed") + "; " + temp.filename().string() +
                       " was removed");
    }
  }
  commit_temp_file(temp, path);
}
} // namespace

std::string particles_xdmf(const XdmfParticles& p) {
  const bool lines = p.n_network_contacts > 0;
  return xdmf_header(lines ? "particles and contact network" : "particles", p.h5_name) +
         configuration_grid(p) + kXdmfFooter;
}

std::string trajectory_xdmf(const std::string& h5_name, const std::vector<XdmfParticles>& frames) {
  std::string grids;
  for (const auto& f : frames) {
    // Each line of the configuration's grid two spaces deeper, inside the temporal collection.
    std::istringstream in(configuration_grid(f));
    for (std::string line; std::getline(in, line);)
      grids += "  " + line + "\n";
  }
  return xdmf_header("trajectory (" + std::to_string(frames.size()) + " snapshots)", h5_name) +
         "    <Grid Name=\"trajectory\" GridType=\"Collection\" CollectionType=\"Temporal\">\n" +
         grids + "    </Grid>\n" + kXdmfFooter;
}

void write_trajectory_xdmf(const std::filesystem::path& xdmf_path, const std::string& h5_name,
                           const std::vector<XdmfParticles>& frames) {
  write_text_atomically(xdmf_path, trajectory_xdmf(h5_name, frames));
}

void write_particles_xdmf(const std::filesystem::path& xdmf_path, const XdmfParticles& p) {
  write_text_atomically(xdmf_path, particles_xdmf(p));
}

void write_modes_xdmf(const std::filesystem::path& xdmf_path, const std::string& h5_name,
                      int dimension, std::int64_t n_grains, int modes, bool rotations,
                      bool divalent_rolling) {
  const std::string file = xml_escape(h5_name), n = std::to_string(n_grains);
  const std::string nd = n + " " + std::to_string(dimension);
  // The file holds numbers as f64 only (io/json_hdf5.h): ids too.
  auto attribute = [&](const std::string& name, const char* kind, const std::string& dims,
                       const std::string& dataset) {
    return "      <Attribute Name=\"" + name + "\" AttributeType=\"" + kind +
           "\" Center=\"Node\">\n        <DataItem Dimensions=\"" + dims +
           "\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">" + file + ":" + dataset +
           "</DataItem>\n      </Attribute>\n";
  };
  std::string grid = "    <Grid Name=\"grains\" GridType=\"Uniform\">\n"
                     "      <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" +
                     n + "\" NodesPerElement=\"1\"/>\n      <Geometry GeometryType=\"" +
                     (dimension == 2 ? "XY" : "XYZ") + "\">\n        <DataItem Dimensions=\"" + nd +
                     "\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">" + file +
                     ":/grains/position</DataItem>\n      </Geometry>\n" +
                     attribute("radius", "Scalar", n, "/grains/radius") +
                     attribute("id", "Scalar", n, "/grains/id") +
                     attribute("backbone", "Scalar", n, "/grains/backbone") +
                     attribute("divalent", "Scalar", n, "/grains/divalent");
  for (int k = 0; k < modes; ++k) {
    const std::string at = "/modes/" + std::to_string(k) + "/", name = "mode_" + std::to_string(k);
    grid += attribute(name, "Vector", nd, at + "displacement");
    if (rotations)
      grid += dimension == 2 ? attribute(name + "_rotation", "Scalar", n, at + "rotation")
                             : attribute(name + "_rotation", "Vector", n + " 3", at + "rotation");
  }
  if (divalent_rolling && dimension == 3) {
    grid += attribute("divalent_rolling", "Vector", nd, "/divalent/rolling/displacement");
    grid += attribute("divalent_rolling_rotation", "Vector", nd, "/divalent/rolling/rotation");
  }
  write_text_atomically(xdmf_path,
                        xdmf_header("stiffness modes (" + std::to_string(modes) + ")", h5_name) +
                            grid + "    </Grid>\n" + kXdmfFooter);
}

} // namespace granpack
