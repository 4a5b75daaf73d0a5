#pragma once
// A defence against HDF5 1.10.8's global heap. A variable-length string is stored as a
// reference (sequence length, global heap collection address, object index) and HDF5 follows
// it trusting every byte: a corrupt collection makes it loop forever or read wild memory, and
// a corrupt length or character size makes it allocate gigabytes (docs/fuzzing.md, "HDF5
// 1.10.8 itself"). check_variable_string() reads the stored reference without conversion,
// then checks the datatype and the collection with plain reads of the file, so that HDF5 is
// only asked to convert a string whose heap object is sound.
#include <hdf5.h>

#include <filesystem>
#include <string>

namespace granpack::h5 {

/// `obj` is an open scalar attribute (is_attribute) or dataset of the file at `path`, whose
/// type is a variable-length string. Returns if HDF5 can convert it safely; otherwise throws
/// InputError("<path>: <what>: <problem>"). Not collective: reads a few kB with POSIX I/O
/// (also when the file is open through MPI-IO), the same bytes on every rank.
void check_variable_string(const std::filesystem::path& path, hid_t obj, bool is_attribute,
                           const std::string& what);

} // namespace granpack::h5
