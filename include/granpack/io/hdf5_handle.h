#pragma once
// RAII ownership of HDF5 identifiers (hid_t) and the checks that turn a failed HDF5 call into a
// granpack exception naming the file and the object. HDF5's own error-stack printing is
// silenced (silence_hdf5_errors); the innermost HDF5 message is appended to ours instead.
#include <hdf5.h>

#include <string>
#include <utility>

namespace granpack::h5 {

/// Turns off HDF5's automatic printing of its error stack (idempotent, cheap).
void silence_errors();

/// The innermost description on HDF5's current error stack ("" if none), e.g.
/// "truncated file: eof = 1024, sblock->base_addr = 0, stored_eof = 4096".
std::string last_error_detail();

/// Owns one hid_t and closes it with the matching H5?close on destruction. Move-only.
class Handle {
public:
  using Closer = herr_t (*)(hid_t);
  Handle() = default;
  Handle(hid_t id, Closer close) : id_(id), close_(close) {}
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  Handle(Handle&& o) noexcept : id_(std::exchange(o.id_, H5I_INVALID_HID)), close_(o.close_) {}
  Handle& operator=(Handle&& o) noexcept {
    if (this != &o) {
      reset();
      id_ = std::exchange(o.id_, H5I_INVALID_HID);
      close_ = o.close_;
    }
    return *this;
  }
  ~Handle() { reset(); }

  hid_t get() const { return id_; }
  operator hid_t() const { return id_; } // NOLINT: used directly in H5 calls
  bool valid() const { return id_ >= 0; }
  /// Gives up ownership without closing; returns the id.
  hid_t release() { return std::exchange(id_, H5I_INVALID_HID); }
  /// Closes now; returns false if H5?close failed (the id is released either way).
  bool reset() {
    bool ok = true;
    if (id_ >= 0 && close_)
      ok = close_(id_) >= 0;
    id_ = H5I_INVALID_HID;
    return ok;
  }

private:
  hid_t id_ = H5I_INVALID_HID;
  Closer close_ = nullptr;
};

inline Handle file_handle(hid_t id) {
  return {id, H5Fclose};
}
inline Handle group_handle(hid_t id) {
  return {id, H5Gclose};
}
inline Handle dataset_handle(hid_t id) {
  return {id, H5Dclose};
}
inline Handle dataspace_handle(hid_t id) {
  return {id, H5Sclose};
}
inline Handle attribute_handle(hid_t id) {
  return {id, H5Aclose};
}
inline Handle datatype_handle(hid_t id) {
  return {id, H5Tclose};
}
inline Handle plist_handle(hid_t id) {
  return {id, H5Pclose};
}

} // namespace granpack::h5
