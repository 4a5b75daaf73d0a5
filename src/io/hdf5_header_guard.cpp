#include "granpack/io/hdf5_header_guard.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <deque>
#include <string>
#include <vector>

#include "granpack/core/error.h"
#include "granpack/io/hdf5_raw_file.h"

namespace granpack::h5 {

namespace {

// The formats below are those of the HDF5 File Format Specification (version 2 and 3 objects),
// read as HDF5 1.10.8 decodes them (H5Ocache.c, H5Oattr.c, H5Osdspace.c, H5Odtype.c). Every
// check asks whether HDF5's read pointer stays inside the message; where HDF5 itself refuses
// a value cleanly (an unknown version, say) we refuse it too, with a clearer message.
constexpr unsigned kContinuation = 0x10, kAttribute = 0x0C;
constexpr unsigned kSharedMessage = 0x02; // message flag: the body is a reference elsewhere
constexpr std::size_t kMaxChunks = 4096;  // a loop of continuations ends here
constexpr unsigned kMaxRank = 32;         // H5S_MAX_RANK
constexpr int kMaxTypeDepth = 16;         // nested vlen/enum/array base types

std::size_t align8(std::size_t n) {
  return (n + 7) / 8 * 8;
}

/// The bytes of one part of a message: reads past its end are problems, not memory errors.
struct Span {
  const unsigned char* p;
  std::size_t n;
};

/// Parses the datatype message in `d` as H5O__dtype_decode_helper does. On success returns ""
/// and sets `used` (the bytes the decoder consumes) and `element` (the size field, which the
/// attribute decoder multiplies by the number of points).
std::string datatype_problem(Span d, std::size_t& used, std::uint64_t& element, int depth) {
  if (depth > kMaxTypeDepth)
    return "datatype nested more than " + std::to_string(kMaxTypeDepth) + " levels deep";
  if (d.n < 8)
    return "datatype of " + std::to_string(d.n) + " bytes (its header alone has 8)";
  const unsigned cls = d.p[0] & 0x0F, version = d.p[0] >> 4;
  if (version < 1 || version > 4)
    return "datatype version " + std::to_string(version) + " (HDF5 knows 1 to 4)";
  const std::uint64_t bits = little_endian(d.p + 1, 3);
  element = little_endian(d.p + 4, 4);
  std::size_t need = 8;
  // The base type of a variable-length, enumeration or array type, at byte `at`: sets `need`
  // past it and `base_element` to its size (the outer size field stays `element`: it is what
  // HDF5 multiplies).
  std::uint64_t base_element = 0;
  auto base = [&](std::size_t at) -> std::string {
    if (at > d.n)
      return "datatype's base type lies past its end";
    std::size_t u = 0;
    auto p = datatype_problem({d.p + at, d.n - at}, u, base_element, depth + 1);
    need = at + u;
    return p;
  };
  switch (cls) {
  case 0: // fixed-point: bit offset, precision
  case 4: // bitfield: the same
    need += 4;
    break;
  case 1: // floating point: offset, precision, exponent and mantissa fields, bias
    need += 12;
    break;
  case 2: // time: precision
    need += 2;
    break;
  case 3: // string, reference: no properties
  case 7:
    break;
  case 5: // opaque: a tag of (bits & 0xff) bytes
    need += bits & 0xFF;
    break;
  case 9: // variable length: its base type
    if (auto p = base(8); !p.empty())
      return p;
    break;
  case 8: { // enumeration: base type, member names, member values
    if (auto p = base(8); !p.empty())
      return p;
    const std::uint64_t value_size = base_element;
    std::size_t at = need;
    const std::uint64_t members = bits & 0xFFFF;
    for (std::uint64_t k = 0; k < members; ++k) {
      const void* nul = at < d.n ? std::memchr(d.p + at, 0, d.n - at) : nullptr;
      if (!nul)
        return "enumeration member " + std::to_string(k) + "'s name runs past the datatype";
      const std::size_t len = static_cast<const unsigned char*>(nul) - (d.p + at) + 1;
      at += version < 3 ? align8(len) : len;
    }
    if (at > d.n || members * value_size > d.n - at)
      return "enumeration values run past the datatype";
    need = at + members * value_size;
    break;
  }
  case 10: { // array: rank, dimensions, (before version 3) permutation, base type
    if (d.n < 9)
      return "array datatype without its rank";
    const unsigned rank = d.p[8];
    if (rank > kMaxRank)
      return "array datatype of rank " + std::to_string(rank) + " (at most 32)";
    const std::size_t at = 9 + (version < 3 ? 3 : 0) + 4 * rank * (version < 3 ? 2 : 1);
    if (auto p = base(at); !p.empty())
      return p;
    break;
  }
  case 6: // compound: the members' layout is left to HDF5 (granpack never writes one)
    need = d.n;
    break;
  default:
    return "datatype class " + std::to_string(cls) + " (HDF5 knows 0 to 10)";
  }
  if (need > d.n)
    return "datatype of class " + std::to_string(cls) + " needs " + std::to_string(need) +
           " bytes, the message gives it " + std::to_string(d.n);
  used = need;
  return "";
}

/// Parses the dataspace message in `d` as H5O__sdspace_decode does; sets `points`.
std::string dataspace_problem(Span d, std::size_t sizeof_length, std::uint64_t& points) {
  if (d.n < 4)
    return "dataspace of " + std::to_string(d.n) + " bytes";
  const unsigned version = d.p[0], rank = d.p[1], flags = d.p[2];
  if (version < 1 || version > 2)
    return "dataspace version " + std::to_string(version) + " (HDF5 knows 1 and 2)";
  if (rank > kMaxRank)
    return "dataspace of rank " + std::to_string(rank) + " (at most 32)";
  unsigned type = rank > 0 ? 1 : 0; // version 1: simple or scalar by rank
  if (version == 2) {
    type = d.p[3];
    if (type > 2)
      return "dataspace type " + std::to_string(type) + " (scalar 0, simple 1, null 2)";
  }
  const std::size_t dims_at = version == 1 ? 8 : 4;
  const std::size_t need = dims_at + rank * sizeof_length * ((flags & 1) ? 2 : 1);
  if (need > d.n)
    return "dataspace of rank " + std::to_string(rank) + " needs " + std::to_string(need) +
           " bytes, the message gives it " + std::to_string(d.n);
  points = type == 0 ? 1 : 0;
  if (type == 1) {
    points = 1;
    for (unsigned k = 0; k < rank; ++k) {
      const std::uint64_t dim = little_endian(d.p + dims_at + k * sizeof_length, sizeof_length);
      if (dim != 0 && points > UINT64_MAX / dim)
        return "dataspace of more than 2^64 points";
      points *= dim;
    }
  }
  return "";
}

/// Parses an attribute message body as H5O__attr_decode does; sets `name` when it can.
std::string attribute_problem(Span b, const FileSizes& s, std::string& name) {
  if (b.n < 8)
    return "message of " + std::to_string(b.n) + " bytes (its header alone has 8)";
  const unsigned version = b.p[0], flags = b.p[1];
  if (version < 1 || version > 3)
    return "attribute message version " + std::to_string(version) + " (HDF5 knows 1 to 3)";
  if (version >= 2 && (flags & 0x03))
    return "attribute with a shared datatype or dataspace (granpack never writes one)";
  if (version >= 2 && (flags & ~0x03u))
    return "attribute message flags " + std::to_string(flags);
  const std::size_t name_size = little_endian(b.p + 2, 2), type_size = little_endian(b.p + 4, 2),
                    space_size = little_endian(b.p + 6, 2);
  // Version 1 pads each part to 8 bytes; version 3 adds the name's character set.
  auto part = [&](std::size_t n) { return version == 1 ? align8(n) : n; };
  const std::size_t name_at = version == 3 ? 9 : 8;
  const std::size_t type_at = name_at + part(name_size), space_at = type_at + part(type_size),
                    data_at = space_at + part(space_size);
  if (name_size == 0 || name_at + name_size > b.n)
    return "its name (" + std::to_string(name_size) + " bytes) runs past the message (" +
           std::to_string(b.n) + " bytes)";
  const unsigned char* nul =
      static_cast<const unsigned char*>(std::memchr(b.p + name_at, 0, name_size));
  if (!nul || std::size_t(nul - (b.p + name_at)) != name_size - 1)
    return "its name is not " + std::to_string(name_size - 1) + " characters and a NUL";
  // Printable as it is, other bytes as \xNN: a corrupt name goes into an error message.
  name.clear();
  for (std::size_t k = 0; k + 1 < name_size; ++k) {
    const unsigned char ch = b.p[name_at + k];
    if (ch >= 0x20 && ch < 0x7F) {
      name += static_cast<char>(ch);
    } else {
      static constexpr char kHex[] = "0123456789abcdef";
      name += {'\\', 'x', kHex[ch >> 4], kHex[ch & 15]};
    }
  }
  if (type_at + type_size > b.n)
    return "its datatype (" + std::to_string(type_size) + " bytes) runs past the message (" +
           std::to_string(b.n) + " bytes)";
  if (space_at + space_size > b.n || data_at > b.n)
    return "its dataspace (" + std::to_string(space_size) + " bytes) runs past the message (" +
           std::to_string(b.n) + " bytes)";
  std::size_t used = 0;
  std::uint64_t element = 0, points = 0;
  if (auto p = datatype_problem({b.p + type_at, type_size}, used, element, 0); !p.empty())
    return p;
  if (auto p = dataspace_problem({b.p + space_at, space_size}, s.length, points); !p.empty())
    return p;
  if (element != 0 && points > (b.n - data_at) / element)
    return "its value (" + std::to_string(points) + " points of " + std::to_string(element) +
           " bytes) runs past the message (" + std::to_string(b.n - data_at) + " bytes left)";
  return "";
}

struct Chunk {
  std::uint64_t at = 0, size = 0; // file offset and length of the messages
};

/// The object header at file offset `at`: its first chunk, the message header size and the
/// version, or a problem.
std::string first_chunk(const RawFile& f, std::uint64_t at, Chunk& c, int& version,
                        std::size_t& message_header) {
  unsigned char h[40] = {};
  const std::size_t n = static_cast<std::size_t>(
      std::min<std::uint64_t>(sizeof h, at < f.size() ? f.size() - at : 0));
  if (n < 16 || !f.read(at, n, h))
    return "the object header lies beyond the end of the file";
  if (std::memcmp(h, "OHDR", 4) == 0) {
    if (h[4] != 2)
      return "object header version " + std::to_string(h[4]) + " (HDF5 knows 1 and 2)";
    const unsigned flags = h[5];
    std::size_t p = 6 + ((flags & 0x20) ? 16 : 0) + ((flags & 0x10) ? 4 : 0);
    const std::size_t width = std::size_t{1} << (flags & 3);
    if (p + width > n)
      return "truncated object header";
    c = {at + p + width, little_endian(h + p, width)};
    version = 2;
    message_header = (flags & 0x04) ? 6 : 4;
    return "";
  }
  if (h[0] != 1)
    return "no object header there (version byte " + std::to_string(h[0]) + ")";
  c = {at + 16, little_endian(h + 8, 4)};
  version = 1;
  message_header = 8;
  return "";
}

} // namespace

void check_attribute_messages(const std::filesystem::path& path, hid_t obj,
                              const std::string& what) {
  const std::string prefix = path.string() + ": " + what + ": ";
  auto fail = [&](const std::string& problem) { throw InputError(prefix + problem); };
  H5O_info_t info{};
  // H5O_INFO_BASIC reads the header's messages without decoding any (the address is all we
  // need); the attribute count would decode them.
  if (H5Oget_info2(obj, &info, H5O_INFO_BASIC) < 0)
    fail("cannot locate the object header");
  FileSizes s;
  if (!file_sizes(obj, s))
    fail("cannot read the file's address sizes");
  RawFile f(path);
  if (!f.ok())
    fail("cannot open the file to check its object header");

  Chunk c;
  int version = 1;
  std::size_t message_header = 8;
  if (auto p = first_chunk(f, s.base + info.addr, c, version, message_header); !p.empty())
    fail("object header at byte " + std::to_string(s.base + info.addr) + ": " + p);
  std::deque<Chunk> chunks{c};
  std::size_t visited = 0, message = 0;
  std::vector<unsigned char> bytes;
  while (!chunks.empty()) {
    c = chunks.front();
    chunks.pop_front();
    if (++visited > kMaxChunks)
      fail("more than " + std::to_string(kMaxChunks) + " object header chunks (a loop?)");
    if (c.at > f.size() || c.size > f.size() - c.at)
      fail("an object header chunk (" + std::to_string(c.size) + " bytes at byte " +
           std::to_string(c.at) + ") runs past the end of the file");
    bytes.resize(static_cast<std::size_t>(c.size));
    if (!f.read(c.at, bytes.size(), bytes.data()))
      fail("cannot read an object header chunk");
    std::size_t p = 0;
    // Version 2 continuation chunks start with "OCHK" and every version 2 chunk ends with a
    // checksum, which the chunk's recorded size already leaves out for the first chunk only.
    std::size_t end = bytes.size();
    if (version == 2 && visited > 1) {
      if (end < 8 || std::memcmp(bytes.data(), "OCHK", 4) != 0)
        fail("an object header continuation chunk without its OCHK signature");
      p = 4, end -= 4;
    }
    while (end - p >= message_header) {
      const unsigned char* m = bytes.data() + p;
      const unsigned type = version == 1 ? unsigned(little_endian(m, 2)) : m[0];
      const std::size_t size = little_endian(m + (version == 1 ? 2 : 1), 2);
      const unsigned flags = version == 1 ? m[4] : m[3];
      const Span body{m + message_header, size};
      if (size > end - p - message_header)
        fail("message " + std::to_string(message) + " (" + std::to_string(size) +
             " bytes) runs past its object header chunk");
      if (type == kContinuation) {
        if (size < s.addr + s.length)
          fail("a continuation message of " + std::to_string(size) + " bytes");
        chunks.push_back(
            {s.base + little_endian(body.p, s.addr), little_endian(body.p + s.addr, s.length)});
      } else if (type == kAttribute) {
        std::string name;
        std::string problem = (flags & kSharedMessage)
                                  ? "a shared attribute message (granpack never writes one)"
                                  : attribute_problem(body, s, name);
        if (!problem.empty())
          fail("attribute message " + std::to_string(message) + " at byte " +
               std::to_string(c.at + p) + (name.empty() ? "" : " ('" + name + "')") +
               " is corrupt: " + problem);
      }
      ++message;
      p += message_header + size;
    }
  }
}

} // namespace granpack::h5
