#pragma once
// Which source tree the running binary was built from, so that a number in report.json or an
// ensemble can be traced to its code (a published table, rerun months later, must say whether
// the same code made it). Generated at every build by src/app/build_info.cmake.

#include <string>

namespace granpack {

/// The source tree's commit (12 hex digits of `git rev-parse HEAD`), or "unknown" when the
/// tree was built outside a git checkout.
extern const char* const build_commit;
/// True when tracked files differed from that commit at build time ("dirty" tree).
extern const bool build_dirty;
/// "granpack VERSION (commit C)" or "... (commit C, uncommitted changes)": the log's first
/// line and --version.
std::string build_description();

} // namespace granpack
