#pragma once
// A defence against HDF5 1.10.8's attribute messages. H5Aexists, H5Aopen and every other
// attribute call decode *all* attribute messages of an object header, and the decoder
// (H5O__attr_decode) trusts the name, datatype and dataspace sizes a message declares: a
// corrupt size moves its read pointer past the message, and it then copies the attribute's
// value from whatever memory follows (found by the fuzz tests under AddressSanitizer: a
// dataspace size of 65 288 in an 80-byte message, an 8-byte read past HDF5's buffer;
// docs/fuzzing.md). check_attribute_messages() walks the object header with plain reads of the
// file first and checks that every attribute message's parts fit inside it, as HDF5 will
// read them, so that HDF5 is only asked to decode sound messages.
#include <hdf5.h>

#include <filesystem>
#include <string>

namespace granpack::h5 {

/// `obj` is an open object (file, group or dataset) of the file at `path`. Returns if every
/// attribute message in its object header is sound; otherwise throws
/// InputError("<path>: <what>: <problem>"). Not collective (POSIX reads of a few kB).
/// Covered: version 1 and 2 object headers with their continuation chunks; attribute messages
/// of versions 1-3, their names, dataspaces and datatypes (all classes but compound, whose
/// members are left to HDF5) and the size of their values. Attributes kept in dense storage
/// (a fractal heap; granpack never writes them) are not reached by this walk.
void check_attribute_messages(const std::filesystem::path& path, hid_t obj,
                              const std::string& what);

} // namespace granpack::h5
