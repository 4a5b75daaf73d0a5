#pragma once
// Where tests find the repository's files and write their scratch output.
#include <filesystem>
#include <string>

namespace granpack::test {
/// The repository root (for decks under jobs/ and tests/decks/).
std::filesystem::path source_dir();
/// A fresh directory under the build tree for this test's files; `tag` keeps tests apart.
/// Not collective: with MPI, pass a name that is the same on all ranks and create it on one.
std::filesystem::path scratch_dir(const std::string& tag);
} // namespace granpack::test
