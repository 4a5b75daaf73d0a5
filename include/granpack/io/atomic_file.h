#pragma once
// Replacing a file so that a crash never leaves it half-written: write a temporary file in the
// same directory, make it durable, then rename() it over the final name (atomic on POSIX).
// Until the rename, the previous file of that name is untouched.
#include <filesystem>

namespace granpack {

/// The temporary name a new version of `path` is written under: "<path>.tmp", same directory
/// (rename is only atomic within one file system).
std::filesystem::path temp_path_for(const std::filesystem::path& path);

/// Not collective. fsyncs the complete `temp`, renames it to `path` (replacing any previous
/// file), then fsyncs the directory. Throws Error naming both paths on failure.
void commit_temp_file(const std::filesystem::path& temp, const std::filesystem::path& path);

} // namespace granpack
