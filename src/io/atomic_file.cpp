#include "granpack/io/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "granpack/core/error.h"

namespace granpack {

namespace {
/// fsync of a file or directory; returns errno (0 on success).
int sync_path(const std::filesystem::path& p, bool directory) {
  int fd = ::open(p.c_str(), directory ? (O_RDONLY | O_DIRECTORY) : O_RDONLY);
  if (fd < 0)
    return errno;
  int rc = ::fsync(fd) == 0 ? 0 : errno;
  ::close(fd);
  return rc;
}
} // namespace

std::filesystem::path temp_path_for(const std::filesystem::path& path) {
  auto temp = path;
  temp += ".tmp";
  return temp;
}

void commit_temp_file(const std::filesystem::path& temp, const std::filesystem::path& path) {
  if (int e = sync_path(temp, false); e != 0)
    throw WriteError("cannot flush " + temp.string() + " to disk: " + std::strerror(e));
  std::error_code ec;
  std::filesystem::rename(temp, path, ec);
  if (ec)
    throw WriteError("cannot rename " + temp.string() + " to " + path.string() + ": " +
                     ec.message());
  // Make the rename itself durable; a failure here leaves a complete file, so it is not fatal.
  auto dir = path.parent_path().empty() ? std::filesystem::path(".") : path.parent_path();
  (void)sync_path(dir, true);
}

} // namespace granpack
