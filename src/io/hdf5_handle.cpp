#include "granpack/io/hdf5_handle.h"

namespace granpack::h5 {

void silence_errors() {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
}

namespace {
herr_t innermost(unsigned n, const H5E_error2_t* e, void* out) {
  // Walking upward, entry 0 is where HDF5 detected the problem: the most specific message.
  if (n == 0 && e->desc)
    *static_cast<std::string*>(out) = e->desc;
  return 0;
}
} // namespace

std::string last_error_detail() {
  std::string detail;
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, innermost, &detail);
  return detail;
}

} // namespace granpack::h5
