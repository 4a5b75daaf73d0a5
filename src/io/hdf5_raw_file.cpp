#include "granpack/io/hdf5_raw_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include "granpack/io/hdf5_handle.h"

namespace granpack::h5 {

std::uint64_t little_endian(const unsigned char* p, std::size_t bytes) {
  std::uint64_t v = 0;
  for (std::size_t k = bytes; k-- > 0;)
    v = (v << 8) | p[k];
  return v;
}

RawFile::RawFile(const std::filesystem::path& path) : fd_(::open(path.c_str(), O_RDONLY)) {
  struct stat st {};
  if (fd_ >= 0 && ::fstat(fd_, &st) == 0)
    size_ = static_cast<std::uint64_t>(st.st_size);
}

RawFile::~RawFile() {
  if (fd_ >= 0)
    ::close(fd_);
}

bool RawFile::read(std::uint64_t offset, std::size_t n, unsigned char* out) const {
  if (offset > size_ || n > size_ - offset)
    return false;
  std::size_t done = 0;
  while (done < n) {
    const ssize_t got = ::pread(fd_, out + done, n - done, static_cast<off_t>(offset + done));
    if (got <= 0)
      return false;
    done += static_cast<std::size_t>(got);
  }
  return true;
}

bool file_sizes(hid_t obj, FileSizes& s) {
  auto file = file_handle(H5Iget_file_id(obj));
  if (!file.valid())
    return false;
  auto fcpl = plist_handle(H5Fget_create_plist(file));
  hsize_t userblock = 0;
  if (!fcpl.valid() || H5Pget_sizes(fcpl, &s.addr, &s.length) < 0 ||
      H5Pget_userblock(fcpl, &userblock) < 0)
    return false;
  s.base = userblock;
  return (s.addr == 2 || s.addr == 4 || s.addr == 8) &&
         (s.length == 2 || s.length == 4 || s.length == 8);
}

} // namespace granpack::h5
