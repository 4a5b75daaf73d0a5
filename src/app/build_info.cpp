// The one wording of "which build is this" for the log's first line and --version (the values
// come from the generated build/generated/build_info.cpp).
#include "granpack/app/build_info.h"

namespace granpack {

std::string build_description() {
  return std::string("granpack " GRANPACK_VERSION " (commit ") + build_commit +
         (build_dirty ? ", uncommitted changes)" : ")");
}

} // namespace granpack
