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

std::string particles_xdmf(const XdmfParticles& p) {
  const std::string file = xml_escape(p.h5_name);
  const std::string n = std::to_string(p.n_particles);
  const std::string nd = n + " " + std::to_string(p.dimension);
  const std::string rd = n + " " + (p.dimension == 2 ? "1" : "3");
  const char* geometry = p.dimension == 2 ? "XY" : "XYZ";
  const bool network = p.n_network_contacts >= 0;
  const bool lines = p.n_network_contacts > 0; // ParaView refuses a grid of no cells
  const std::string ind = network ? "  " : ""; // the grids sit inside a collection
  auto item = [&](const std::string& dims, const char* type, const std::string& dataset) {
    return ind + "        <DataItem Dimensions=\"" + dims + "\" NumberType=\"" + type +
           "\" Precision=\"8\" Format=\"HDF\">" + file + ":" + dataset + "</DataItem>\n";
  };
  auto attribute = [&](const char* name, const char* kind, const char* center,
                       const std::string& dims, const char* type, const std::string& dataset) {
    return ind + "      <Attribute Name=\"" + name + "\" AttributeType=\"" + kind + "\" Center=\"" +
           center + "\">\n" + item(dims, type, dataset) + ind + "      </Attribute>\n";
  };
  std::ostringstream os;
  os.precision(17);
  os << "<?xml version=\"1.0\" ?>\n"
     << "<!-- granpack particles" << (lines ? " and contact network" : "") << "; data in " << file
     << " (see docs/hdf5-schema.md, docs/visualisation.md) -->\n"
     << "<Xdmf Version=\"3.0\">\n"
     << "  <Domain>\n";
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
       << attribute("mean_stress", "Scalar", "Node", n, "Float", "/network/mean_stress");
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
       << attribute("kind", "Scalar", "Cell", nc, "Int", "/network/kind") << "      </Grid>\n";
  }
  if (network)
    os << "    </Grid>\n";
  os << "  </Domain>\n"
     << "</Xdmf>\n";
  return os.str();
}

void write_particles_xdmf(const std::filesystem::path& xdmf_path, const XdmfParticles& p) {
  const auto temp = temp_path_for(xdmf_path);
  {
    errno = 0;
    std::ofstream out(temp, std::ios::binary | std::ios::trunc);
    out << particles_xdmf(p);
    out.close();
    if (!out) {
      const int e = errno; // set by the failed write or close (ENOSPC, EDQUOT, EFBIG)
      std::error_code ec;
      std::filesystem::remove(temp, ec);
      throw WriteError("cannot write " + xdmf_path.string() + ": " +
                       (e ? std::strerror(e) : "write failed") + "; " + temp.filename().string() +
                       " was removed");
    }
  }
  commit_temp_file(temp, xdmf_path);
}

} // namespace granpack
