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
  auto item = [&](const std::string& dims, const char* type, const std::string& dataset) {
    return "        <DataItem Dimensions=\"" + dims + "\" NumberType=\"" + type +
           "\" Precision=\"8\" Format=\"HDF\">" + file + ":" + dataset + "</DataItem>\n";
  };
  std::ostringstream os;
  os.precision(17);
  os << "<?xml version=\"1.0\" ?>\n"
     << "<!-- granpack particles; data in " << file << " (see docs/hdf5-schema.md) -->\n"
     << "<Xdmf Version=\"3.0\">\n"
     << "  <Domain>\n"
     << "    <Grid Name=\"particles\" GridType=\"Uniform\">\n"
     << "      <Time Value=\"" << p.time << "\"/>\n"
     << "      <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" << n
     << "\" NodesPerElement=\"1\"/>\n"
     << "      <Geometry GeometryType=\"" << (p.dimension == 2 ? "XY" : "XYZ") << "\">\n"
     << item(nd, "Float", "/particles/position") << "      </Geometry>\n"
     << "      <Attribute Name=\"radius\" AttributeType=\"Scalar\" Center=\"Node\">\n"
     << item(n, "Float", "/particles/radius") << "      </Attribute>\n"
     << "      <Attribute Name=\"id\" AttributeType=\"Scalar\" Center=\"Node\">\n"
     << item(n, "Int", "/particles/id") << "      </Attribute>\n"
     << "      <Attribute Name=\"velocity\" AttributeType=\"Vector\" Center=\"Node\">\n"
     << item(nd, "Float", "/particles/velocity") << "      </Attribute>\n"
     << "    </Grid>\n"
     << "  </Domain>\n"
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
