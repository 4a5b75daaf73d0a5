// libFuzzer driver of the HDF5 configuration reader (docs/fuzzing.md): each input is written
// to a private temporary file and read with read_file_meta, describe_file and
// read_configuration<3> and <2> on MPI_COMM_SELF. The property is check_h5 of fuzz_inputs.h;
// a violation aborts. Mutations: libFuzzer's own, the byte-level ones of the CI corpus, and
// structural ones through the HDF5 API (deleted/reshaped/retyped datasets and attributes,
// huge declared sizes, bad ids and keys, links).
//
// GRANPACK_FUZZ_SEEDS_DIR=DIR h5_fuzzer   writes the seed files (3-D, 2-D, no contacts) to DIR
// and exits: use DIR as the initial corpus.
#include <mpi.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "fuzz_inputs.h"

extern "C" size_t LLVMFuzzerMutate(uint8_t* data, size_t size, size_t max_size);

namespace {
namespace fs = std::filesystem;
fs::path& work_dir() {
  static fs::path d;
  return d;
}
} // namespace

extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv) {
  MPI_Init(argc, argv);
  std::string tmpl = (fs::temp_directory_path() / "granpack_h5fuzz_XXXXXX").string();
  work_dir() = mkdtemp(tmpl.data());
  if (const char* dir = std::getenv("GRANPACK_FUZZ_SEEDS_DIR")) {
    fs::create_directories(dir);
    granpack::fuzz::write_seed_file<3>(fs::path(dir) / "seed3.h5", 9, 1);
    granpack::fuzz::write_seed_file<2>(fs::path(dir) / "seed2.h5", 7, 2);
    granpack::fuzz::write_seed_file<3>(fs::path(dir) / "seed0.h5", 1, 3);
    std::printf("seed files written to %s\n", dir);
    MPI_Finalize();
    std::exit(0);
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const fs::path input = work_dir() / "input.h5";
  granpack::fuzz::write_bytes(input, std::string(reinterpret_cast<const char*>(data), size));
  granpack::fuzz::abort_if_violated(granpack::fuzz::check_h5(input, work_dir()));
  return 0;
}

extern "C" size_t LLVMFuzzerCustomMutator(uint8_t* data, size_t size, size_t max_size,
                                          unsigned int seed) {
  granpack::fuzz::Rng rng(seed);
  const auto how = rng.below(3);
  if (how == 0)
    return LLVMFuzzerMutate(data, size, max_size);
  std::string bytes(reinterpret_cast<const char*>(data), size);
  if (how == 1) {
    granpack::fuzz::mutate_h5_bytes(bytes, rng);
  } else {
    const fs::path scratch = work_dir() / "mutate.h5";
    granpack::fuzz::write_bytes(scratch, bytes);
    granpack::fuzz::mutate_h5_structure(scratch, rng);
    bytes = granpack::fuzz::read_bytes(scratch);
  }
  if (bytes.size() > max_size)
    bytes.resize(max_size);
  std::memcpy(data, bytes.data(), bytes.size());
  return bytes.size();
}
