#pragma once
// Writes a JSON document (the results of `granpack analyze`) as an HDF5 file, so that curves
// and histograms can be read as arrays with h5py, ParaView or MATLAB: objects become groups,
// arrays of numbers become 1-D f64 datasets (arrays of equal-length number arrays, 2-D),
// numbers, booleans and strings become attributes of their group; nulls are left out.
// Object keys are used as names ('/' replaced by '_'). Serial: call on one rank. The file is
// written under a temporary name and renamed when complete.
#include <filesystem>
#include <nlohmann/json.hpp>

namespace granpack {

void write_json_as_hdf5(const std::filesystem::path& path, const nlohmann::json& doc);

} // namespace granpack
