#pragma once
// Plain reads of an HDF5 file's bytes, for the guards (hdf5_string_guard.h,
// hdf5_header_guard.h) that check structures HDF5 1.10.8 would otherwise follow blindly. The
// guards read with POSIX calls, independent of the driver HDF5 opened the file with (MPI-IO
// or not), so that a check reads the same bytes on every rank and costs no collective call.
#include <hdf5.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>

namespace granpack::h5 {

/// The unsigned little-endian integer of `bytes` bytes at p (HDF5 stores every field so).
std::uint64_t little_endian(const unsigned char* p, std::size_t bytes);

/// The file opened read-only with POSIX calls.
class RawFile {
public:
  explicit RawFile(const std::filesystem::path& path);
  ~RawFile();
  RawFile(const RawFile&) = delete;
  RawFile& operator=(const RawFile&) = delete;

  bool ok() const { return fd_ >= 0; }
  std::uint64_t size() const { return size_; }
  /// Reads [offset, offset + n) entirely, or returns false.
  bool read(std::uint64_t offset, std::size_t n, unsigned char* out) const;

private:
  int fd_ = -1;
  std::uint64_t size_ = 0;
};

/// What the superblock says about addresses.
struct FileSizes {
  std::size_t addr = 8, length = 8; // sizeof_addr, sizeof_size
  std::uint64_t base = 0;           // where address 0 is: the userblock's size
};

/// The address and length sizes and the base of `obj`'s file; false if HDF5 cannot tell or
/// the sizes are not 2, 4 or 8 bytes.
bool file_sizes(hid_t obj, FileSizes& s);

} // namespace granpack::h5
