#include "granpack/io/mpiio_hints.h"

#include <cstdlib>

#include "granpack/core/error.h"

namespace granpack {

namespace {
constexpr const char* kVariable = "GRANPACK_MPIIO_HINTS";

const char* hints_text() {
  const char* env = std::getenv(kVariable);
  return env != nullptr ? env : "";
}
} // namespace

std::vector<std::pair<std::string, std::string>> parse_mpiio_hints(const std::string& text) {
  std::vector<std::pair<std::string, std::string>> hints;
  std::size_t pos = 0;
  while (pos < text.size()) {
    const std::size_t end = text.find_first_of(",; \t\n", pos);
    const std::string entry =
        text.substr(pos, end == std::string::npos ? std::string::npos : end - pos);
    pos = end == std::string::npos ? text.size() : end + 1;
    if (entry.empty())
      continue;
    const std::size_t eq = entry.find('=');
    // MPI_MAX_INFO_KEY is 255 characters in Open MPI and MPICH (the standard's minimum: 32).
    if (eq == 0 || eq == std::string::npos || eq + 1 == entry.size() || eq >= MPI_MAX_INFO_KEY)
      throw InputError(std::string(kVariable) + "=\"" + text + "\": '" + entry +
                       "' is not key=value (e.g. " + kVariable +
                       "=\"romio_cb_write=enable,cb_nodes=8\"; docs/long-jobs.md)");
    hints.emplace_back(entry.substr(0, eq), entry.substr(eq + 1));
  }
  return hints;
}

void check_mpiio_hints() {
  parse_mpiio_hints(hints_text());
}

MPI_Info mpiio_hints_info() {
  const auto hints = parse_mpiio_hints(hints_text());
  if (hints.empty())
    return MPI_INFO_NULL;
  MPI_Info info = MPI_INFO_NULL;
  MPI_Info_create(&info);
  for (const auto& [key, value] : hints)
    MPI_Info_set(info, key.c_str(), value.c_str());
  return info;
}

} // namespace granpack
