#pragma once
// One run per output directory: DIR/.lock is held (flock) by rank 0 of the run writing there,
// so that a second run started into the same directory is refused before it truncates the
// first one's log.txt or collides with its temporary files. The lock dies with the process
// (a killed run leaves no stale lock to clear by hand).
#include <filesystem>
#include <string>

namespace granpack {

class OutputLock {
public:
  OutputLock() = default;
  /// Takes DIR/.lock; throws InputError if another process holds it. On file systems without
  /// flock (some parallel file systems) returns without a lock and says so in `warning()`.
  explicit OutputLock(const std::filesystem::path& dir);
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;
  OutputLock(OutputLock&& other) noexcept;
  OutputLock& operator=(OutputLock&& other) noexcept;
  ~OutputLock();

  /// Empty, or why no lock could be taken (the run goes on without one).
  const std::string& warning() const { return warning_; }

private:
  void release() noexcept;
  int fd_ = -1;
  std::filesystem::path path_;
  std::string warning_;
};

} // namespace granpack
