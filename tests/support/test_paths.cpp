#include "test_paths.h"

namespace granpack::test {
std::filesystem::path source_dir() {
  return GRANPACK_SOURCE_DIR;
}
std::filesystem::path scratch_dir(const std::string& tag) {
  auto dir = std::filesystem::path(GRANPACK_BINARY_DIR) / "test-scratch" / tag;
  std::filesystem::create_directories(dir);
  return dir;
}
} // namespace granpack::test
