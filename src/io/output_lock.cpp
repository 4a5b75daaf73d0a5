#include "granpack/io/output_lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <utility>

#include "granpack/core/error.h"

namespace granpack {

OutputLock::OutputLock(const std::filesystem::path& dir) : path_(dir / ".lock") {
  fd_ = ::open(path_.c_str(), O_CREAT | O_RDWR | O_CLOEXEC, 0644);
  if (fd_ < 0) {
    warning_ = "cannot create " + path_.string() + " (" + std::strerror(errno) +
               "): running without the one-run-per-directory lock";
    return;
  }
  if (::flock(fd_, LOCK_EX | LOCK_NB) == 0)
    return;
  const int err = errno;
  ::close(fd_);
  fd_ = -1;
  if (err == EWOULDBLOCK)
    throw InputError("another granpack run is writing into " + dir.string() + " (it holds " +
                     path_.string() + "): wait for it to end, or give this run another -o");
  warning_ = "cannot lock " + path_.string() + " (" + std::strerror(err) +
             "): running without the one-run-per-directory lock";
}

OutputLock::OutputLock(OutputLock&& other) noexcept
    : fd_(std::exchange(other.fd_, -1)), path_(std::move(other.path_)),
      warning_(std::move(other.warning_)) {}

OutputLock& OutputLock::operator=(OutputLock&& other) noexcept {
  if (this != &other) {
    release();
    fd_ = std::exchange(other.fd_, -1);
    path_ = std::move(other.path_);
    warning_ = std::move(other.warning_);
  }
  return *this;
}

OutputLock::~OutputLock() {
  release();
}

void OutputLock::release() noexcept {
  if (fd_ < 0)
    return;
  // Unlink while still holding the lock: a run that opens the path afterwards creates a new
  // file and locks that one, so two runs never both believe they hold the same lock.
  ::unlink(path_.c_str());
  ::close(fd_);
  fd_ = -1;
}

} // namespace granpack
