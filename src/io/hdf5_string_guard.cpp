#include "granpack/io/hdf5_string_guard.h"

#include <cstdint>
#include <cstring>
#include <mutex>
#include <vector>

#include "granpack/core/error.h"
#include "granpack/io/hdf5_handle.h"
#include "granpack/io/hdf5_raw_file.h"

namespace granpack::h5 {

namespace {

// The global heap's file format (HDF5 File Format Specification, "Global Heap"), as HDF5
// 1.10.8 decodes it (H5HGcache.c): a collection is "GCOL", version 1, 3 reserved bytes, its
// size (sizeof_size bytes, header included), then objects: index (2 bytes), reference count
// (2), reserved (4), size (sizeof_size), data padded to 8 bytes. Index 0 is the free space,
// whose size includes its header and is not padded.
constexpr char kSignature[4] = {'G', 'C', 'O', 'L'};
constexpr unsigned kVersion = 1;
constexpr std::uint64_t kMinCollectionSize = 4096; // H5HG_MINSIZE: HDF5 never writes less

/// Tags the opaque memory type that receives a stored reference byte for byte.
constexpr const char* kRawTag = "granpack: stored variable-length reference";

/// A soft conversion "variable-length string -> our opaque type" that leaves the bytes as
/// they are: HDF5 hands a conversion function the element in its stored (disk) form, so
/// H5Aread/H5Dread with the opaque type returns the reference without following it. There is
/// no public call for these bytes in 1.10.8 (H5Aget_storage_size gives only their count).
herr_t keep_stored_bytes(hid_t src, hid_t dst, H5T_cdata_t* cdata, size_t, size_t, size_t, void*,
                         void*, hid_t) {
  switch (cdata->command) {
  case H5T_CONV_INIT: {
    // Refuse every other pair, so no conversion of anyone else's types is taken over.
    if (H5Tis_variable_str(src) <= 0 || H5Tget_class(dst) != H5T_OPAQUE)
      return -1;
    char* tag = H5Tget_tag(dst);
    const bool ours = tag && std::strcmp(tag, kRawTag) == 0;
    H5free_memory(tag);
    // Same size: the stored reference is 4 + sizeof_addr + 4 bytes, as the opaque type.
    if (!ours || H5Tget_size(src) != H5Tget_size(dst))
      return -1;
    cdata->need_bkg = H5T_BKG_NO;
    return 0;
  }
  case H5T_CONV_CONV: // in place, same size: the bytes are already where they belong
  case H5T_CONV_FREE:
    return 0;
  }
  return -1;
}

void register_raw_conversion() {
  static std::once_flag once;
  std::call_once(once, [] {
    auto src = datatype_handle(H5Tcopy(H5T_C_S1));
    H5Tset_size(src, H5T_VARIABLE);
    auto dst = datatype_handle(H5Tcreate(H5T_OPAQUE, 16));
    H5Tset_tag(dst, kRawTag);
    H5Tregister(H5T_PERS_SOFT, "granpack_keep_stored_vlen", src, dst, keep_stored_bytes);
  });
}

/// Walks the collection at file offset `at` as HDF5 will and checks that object `index` is
/// there with `length` bytes. Returns "" or what is wrong.
std::string collection_problem(const RawFile& f, const FileSizes& s, std::uint64_t at,
                               std::uint64_t index, std::uint64_t length) {
  const std::size_t header = 4 + 1 + 3 + s.length, object_header = 2 + 2 + 4 + s.length;
  if (at >= f.size() || f.size() - at < header)
    return "the collection's header lies beyond the end of the file (" + std::to_string(f.size()) +
           " bytes)";
  std::vector<unsigned char> head(header);
  if (!f.read(at, header, head.data()))
    return "cannot read the collection's header";
  if (std::memcmp(head.data(), kSignature, 4) != 0)
    return "no global heap collection there (signature is not GCOL)";
  if (head[4] != kVersion)
    return "global heap collection version " + std::to_string(head[4]) + " (HDF5 knows 1)";
  const std::uint64_t size = little_endian(head.data() + 8, s.length);
  if (size < kMinCollectionSize || size > f.size() - at)
    return "the collection claims " + std::to_string(size) + " bytes (need " +
           std::to_string(kMinCollectionSize) + " to the " + std::to_string(f.size() - at) +
           " bytes left in the file)";
  // Bounded by the file's size, and HDF5 reads the whole collection next anyway.
  std::vector<unsigned char> c(static_cast<std::size_t>(size));
  if (!f.read(at, c.size(), c.data()))
    return "cannot read the collection's " + std::to_string(size) + " bytes";

  std::vector<bool> seen(65536, false);
  bool found = false;
  std::uint64_t found_size = 0;
  // Every object advances the walk by at least one object header: at most size/16 turns.
  for (std::uint64_t p = header; p < size;) {
    if (size - p < object_header)
      break; // HDF5 counts a tail too short for an object header as free space
    const unsigned idx = static_cast<unsigned>(little_endian(&c[p], 2));
    const std::uint64_t osize = little_endian(&c[p + 8], s.length);
    const std::string where =
        "object " + std::to_string(idx) + " at byte " + std::to_string(p) + " of the collection";
    if (osize > size)
      return where + " claims " + std::to_string(osize) + " bytes, more than the collection's " +
             std::to_string(size);
    // Index 0, the free space, counts its header and is not padded; other objects are.
    const std::uint64_t need = idx == 0 ? osize : object_header + ((osize + 7) / 8) * 8;
    if (need < object_header || need > size - p)
      return where + " claims " + std::to_string(osize) + " bytes, which " +
             (need < object_header ? "is less than its own header"
                                   : "runs past the collection's end") +
             " (HDF5 1.10.8 would loop or read out of bounds)";
    if (idx != 0) {
      if (seen[idx])
        return "object index " + std::to_string(idx) + " appears twice in the collection";
      seen[idx] = true;
      if (idx == index) {
        found = true;
        found_size = osize;
      }
    }
    p += need;
  }
  if (index == 0 || !found)
    return "object " + std::to_string(index) + " is not in the collection";
  if (found_size != length)
    return "object " + std::to_string(index) + " holds " + std::to_string(found_size) +
           " bytes but the string claims " + std::to_string(length);
  return "";
}

} // namespace

void check_variable_string(const std::filesystem::path& path, hid_t obj, bool is_attribute,
                           const std::string& what) {
  const std::string prefix = path.string() + ": " + what + ": ";
  auto fail = [&](const std::string& problem) { throw InputError(prefix + problem); };

  // A character size other than 1 multiplies the length HDF5 allocates (a flipped size
  // field of 4294967041 bytes made it allocate 21 GB for a 5-character string).
  auto type = datatype_handle(is_attribute ? H5Aget_type(obj) : H5Dget_type(obj));
  auto base = datatype_handle(type.valid() ? H5Tget_super(type) : H5I_INVALID_HID);
  if (!base.valid())
    fail("cannot read the character type of the variable-length string");
  if (H5Tget_size(base) != 1)
    fail("variable-length string of " + std::to_string(H5Tget_size(base)) +
         "-byte characters (corrupt datatype; a string has 1-byte characters)");

  FileSizes s;
  if (!file_sizes(obj, s))
    fail("cannot read the file's address sizes");
  register_raw_conversion();
  const std::size_t ref_size = 4 + s.addr + 4;
  auto raw = datatype_handle(H5Tcreate(H5T_OPAQUE, ref_size));
  if (!raw.valid() || H5Tset_tag(raw, kRawTag) < 0)
    fail("cannot create a type for the stored reference");
  std::vector<unsigned char> ref(ref_size);
  const herr_t rc = is_attribute ? H5Aread(obj, raw, ref.data())
                                 : H5Dread(obj, raw, H5S_ALL, H5S_ALL, H5P_DEFAULT, ref.data());
  if (rc < 0)
    fail("cannot read the stored reference of the variable-length string (HDF5: " +
         last_error_detail() + ")");
  const std::uint64_t length = little_endian(ref.data(), 4);
  const std::uint64_t address = little_endian(ref.data() + 4, s.addr);
  const std::uint64_t index = little_endian(ref.data() + 4 + s.addr, 4);
  if (address == 0)
    return; // a null string: HDF5 reads no heap

  RawFile f(path);
  if (!f.ok())
    fail("cannot open the file to check its global heap");
  const std::uint64_t at = s.base + address;
  std::string problem =
      at < address ? "address overflow" : collection_problem(f, s, at, index, length);
  if (!problem.empty())
    fail("the string (" + std::to_string(length) + " bytes, global heap collection at byte " +
         std::to_string(at) + ", object " + std::to_string(index) + ") is corrupt: " + problem);
}

} // namespace granpack::h5
