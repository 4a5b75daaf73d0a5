#pragma once
// Error kinds and checks. Exit codes are part of the user interface (docs/cli.md):
//   0 success; 1 runtime failure; 2 bad input (deck, command line, unreadable input file);
//   3 feature not implemented yet; 74 a file could not be written (disk full, quota, file
//   size limit: EX_IOERR of sysexits.h; the previous checkpoint is intact); 75 stopped on
//   request after writing a checkpoint (resubmit with --restart; 75 is EX_TEMPFAIL of
//   sysexits.h: "try again later").
// Which ranks know about an error matters under MPI (docs/ARCHITECTURE.md, "Errors"):
// errors known on every rank are thrown from code all ranks run; errors seen on one rank
// are recorded and all-reduced at a sync point (comm/collective_error.h).
#include <sstream>
#include <stdexcept>
#include <string>

namespace granpack {

enum ExitCode : int {
  kExitOk = 0,
  kExitFailure = 1,
  kExitBadInput = 2,
  kExitNotImplemented = 3,
  kExitWriteFailed = 74,
  kExitCheckpointed = 75,
};

/// Base of granpack's exceptions; carries the process exit code it maps to.
class Error : public std::runtime_error {
public:
  explicit Error(const std::string& what, int exit_code = kExitFailure)
      : std::runtime_error(what), exit_code_(exit_code) {}
  int exit_code() const { return exit_code_; }

private:
  int exit_code_;
};

/// Bad user input: a deck key, a command-line argument, an unreadable or corrupt file.
class InputError : public Error {
public:
  explicit InputError(const std::string& what) : Error(what, kExitBadInput) {}
};

/// A feature that is specified but not implemented in this version.
class NotImplemented : public Error {
public:
  explicit NotImplemented(const std::string& what) : Error(what, kExitNotImplemented) {}
};

/// An output file could not be written (no space left, quota, EFBIG): exit code 74. Thrown on
/// every rank together, after the temporary file was removed (docs/long-jobs.md).
class WriteError : public Error {
public:
  explicit WriteError(const std::string& what) : Error(what, kExitWriteFailed) {}
};

/// Not a failure: the run stopped on a signal after writing a checkpoint (exit code 75).
class CheckpointedStop : public Error {
public:
  explicit CheckpointedStop(const std::string& what) : Error(what, kExitCheckpointed) {}
};

namespace detail {
[[noreturn]] inline void check_failed(const char* cond, const std::string& msg, const char* file,
                                      int line) {
  std::ostringstream os;
  os << msg << " [check '" << cond << "' failed at " << file << ":" << line << "]";
  throw Error(os.str());
}
} // namespace detail

} // namespace granpack

/// Always-on check: throws granpack::Error with the message (streamable) when cond is false.
#define GRANPACK_CHECK(cond, msg)                                                                  \
  do {                                                                                             \
    if (!(cond)) {                                                                                 \
      std::ostringstream granpack_check_os_;                                                       \
      granpack_check_os_ << msg;                                                                   \
      ::granpack::detail::check_failed(#cond, granpack_check_os_.str(), __FILE__, __LINE__);       \
    }                                                                                              \
  } while (0)

/// Debug-only assertion: compiled out in Release builds (NDEBUG).
#ifdef NDEBUG
#define GRANPACK_ASSERT(cond, msg) ((void)0)
#else
#define GRANPACK_ASSERT(cond, msg) GRANPACK_CHECK(cond, msg)
#endif
