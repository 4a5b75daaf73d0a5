#include "granpack/io/log.h"

#include <iostream>

#include "granpack/core/error.h"

namespace granpack {

void Log::open_file(const std::string& path, bool append) {
  if (!root_)
    return;
  file_ = std::make_unique<std::ofstream>(path, append ? std::ios::app : std::ios::trunc);
  if (!*file_)
    throw Error("cannot write the log file " + path);
}

void Log::emit(const std::string& line, bool to_stderr) {
  if (!root_)
    return;
  (to_stderr ? std::cerr : std::cout) << prefix_ << line << std::endl;
  emit_to_file(line);
}

void Log::emit_to_file(const std::string& line) {
  if (root_ && file_)
    *file_ << line << std::endl;
}

} // namespace granpack
