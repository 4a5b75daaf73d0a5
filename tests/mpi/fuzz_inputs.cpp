// Bounded, seeded fuzzing of the two readers of user files (issue 7): the deck parser and the
// HDF5 configuration reader. Every input must be accepted or refused with an InputError that
// names the file, in bounded time, without a crash or stray HDF5 output (the property is in
// tests/fuzz/fuzz_inputs.h; docs/fuzzing.md has the long campaigns and the bugs found).
//
// Deterministic: input i is generated from (seed, i) alone, so the corpus is the same at any
// rank count; with P ranks, rank r checks inputs i = r mod P. Counts and seed can be raised
// for a campaign without recompiling:
//   GRANPACK_FUZZ_DECKS=200000 GRANPACK_FUZZ_H5=20000 GRANPACK_FUZZ_SEED=7 mpi_fuzz_inputs
// A failing input is saved under <build>/test-scratch/fuzz_failures/ for reproduction.
#include <gtest/gtest.h>
#include <mpi.h>
#include <stdlib.h>
#include <sys/resource.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "../fuzz/fuzz_inputs.h"
#include "granpack/io/hdf5_header_guard.h"
#include "mpi_world.h"
#include "test_paths.h"

using namespace granpack;
namespace fs = std::filesystem;

namespace {

using test::world_rank;
using test::world_size;

// CPU seconds this process has used: complexity guards use it rather than the wall clock, which
// other jobs on the machine stretch.
double cpu_seconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

// Peak resident set size of this process so far, in KiB (Linux ru_maxrss).
long peak_rss_kib() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss;
}
std::int64_t sum_over_ranks(std::int64_t x) {
  std::int64_t s = 0;
  MPI_Allreduce(&x, &s, 1, MPI_INT64_T, MPI_SUM, MPI_COMM_WORLD);
  return s;
}
double max_over_ranks(double x) {
  double m = 0;
  MPI_Allreduce(&x, &m, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  return m;
}

std::uint64_t env_count(const char* name, std::uint64_t fallback) {
  const char* v = std::getenv(name);
  return v && *v ? std::strtoull(v, nullptr, 10) : fallback;
}
std::uint64_t fuzz_seed() {
  return env_count("GRANPACK_FUZZ_SEED", 20261201);
}

/// The generator of input i: independent of the rank count.
fuzz::Rng input_rng(std::uint64_t salt, std::uint64_t i) {
  return fuzz::Rng(fuzz_seed() * 0x9E3779B97F4A7C15ULL ^ (salt << 40) ^ i);
}

/// A private temporary directory of this rank, removed on destruction.
struct TempDir {
  fs::path path;
  TempDir() {
    std::string tmpl = (fs::temp_directory_path() / "granpack_fuzz_XXXXXX").string();
    path = mkdtemp(tmpl.data());
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

fs::path failure_dir() {
  const auto d = granpack::test::scratch_dir("fuzz_failures");
  return d;
}

// GCC marks ASan with __SANITIZE_ADDRESS__, clang with __has_feature. GCC's macro is tested
// first: Eigen (included through fuzz_inputs.h) defines __has_feature(x) as 0 for compilers
// without it, which made GCC + ASan builds cap the address space and fail.
#if defined(__SANITIZE_ADDRESS__)
constexpr bool kAddressSanitizer = true;
#elif defined(__has_feature)
constexpr bool kAddressSanitizer = __has_feature(address_sanitizer);
#else
constexpr bool kAddressSanitizer = false;
#endif

/// HDF5 1.10.8 allocates and clears whatever length a corrupt variable-length string claims,
/// tens of GB for a 17 kB file (docs/fuzzing.md, "Not fixed in granpack"). While fuzzing, the
/// address space is capped so that such an input fails an allocation inside HDF5 (a refusal,
/// counted apart) instead of taking the machine's memory. Not under ASan, whose shadow memory
/// needs terabytes of address space (libFuzzer's -malloc_limit_mb does this job there).
class AddressSpaceCap {
public:
  explicit AddressSpaceCap(rlim_t bytes) {
    if (kAddressSanitizer || getrlimit(RLIMIT_AS, &old_) != 0)
      return;
    rlimit cap = old_;
    cap.rlim_cur = std::min(old_.rlim_max, bytes);
    active_ = setrlimit(RLIMIT_AS, &cap) == 0;
  }
  ~AddressSpaceCap() {
    if (active_)
      setrlimit(RLIMIT_AS, &old_);
  }

private:
  rlimit old_{};
  bool active_ = false;
};

constexpr int kMaxReported = 10; // failures printed in full; all are counted

/// Counts a violation; the first kMaxReported are reported in full with the saved input.
void report(std::int64_t& failed, const std::string& input, const fs::path& saved,
            const std::string& verdict) {
  if (++failed <= kMaxReported)
    ADD_FAILURE() << input << " (saved as " << saved.string() << "): " << verdict;
}

} // namespace

// ------------------------------------------------------------------------------------------
// Regressions: one case per bug the fuzzing found (docs/fuzzing.md), with the expected text.

namespace {
std::string deck_message(const std::string& text) {
  try {
    parse_deck(text, "r.toml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "(accepted)";
}
const char* kHead = "[sample]\ndimension = 3\nn = 256\ndiameter = 1e-3\n"
                    "[material]\ndensity = 2500.0\nyoung_modulus = 7e10\npoisson_ratio = 0.3\n"
                    "friction = 0.3\ndamping = 0.9\n";
const char* kLattice = "[[stage]]\nkind = \"lattice\"\nphi = 0.6\n";
} // namespace

TEST(FuzzRegressions, DeepArraysAreRefusedNotAStackOverflow) {
  // toml11 recursed once per level: 10^4 nested arrays overflowed the stack (SIGSEGV).
  const std::string deep = "x = " + std::string(100000, '[') + std::string(100000, ']') + "\n";
  EXPECT_EQ(deck_message(kHead + deep + kLattice),
            "r.toml:11: arrays, inline tables or dotted keys nested more than 64 levels deep "
            "(see docs/deck.md)");
  // The line is right after unterminated strings (found by the fuzzer: counted twice).
  EXPECT_EQ(deck_message("a = \"open\nb = 'open\nc = \"\\\n" + deep),
            "r.toml:4: arrays, inline tables or dotted keys nested more than 64 levels deep "
            "(see docs/deck.md)");
  std::string tables = "x = ";
  for (int i = 0; i < 100000; ++i)
    tables += "{a=";
  EXPECT_NE(deck_message(kHead + tables + "\n" + kLattice).find("r.toml:11: arrays, inline"),
            std::string::npos);
}

TEST(FuzzRegressions, LongDottedKeysAreRefusedQuickly) {
  // toml11 handled a dotted key in quadratic time: 10^5 parts took minutes (a hang).
  std::string key = "[sample";
  for (int i = 0; i < 100000; ++i)
    key += ".x";
  // The guard is this process's CPU time, not the wall clock, so that a loaded machine cannot
  // fail it: linear parsing takes milliseconds, the quadratic one took minutes.
  const double cpu0 = cpu_seconds();
  EXPECT_EQ(deck_message(key + "]\n" + kHead + kLattice),
            "r.toml:1: arrays, inline tables or dotted keys nested more than 64 levels deep "
            "(see docs/deck.md)");
  EXPECT_LT(cpu_seconds() - cpu0, 10.0);
  // A deck needs none of this: the 64-level limit leaves every real deck alone.
  for (const auto& seed : fuzz::deck_seeds(granpack::test::source_dir()))
    EXPECT_EQ(deck_message(seed).find("nested more than"), std::string::npos);
}

TEST(FuzzRegressions, NumbersBeyond64BitsOrDoublesAreRefused) {
  // toml11 clamped these to INT64_MAX / DBL_MAX (0b literals wrapped) and the deck was
  // accepted with a value the user never wrote.
  auto with_seed = [](const std::string& v) {
    std::string h = kHead;
    h.insert(h.find("[material]"), "seed = " + v + "\n");
    return deck_message(h + kLattice);
  };
  EXPECT_EQ(with_seed("99999999999999999999"),
            "r.toml:5: [sample] seed: = 99999999999999999999 does not fit in a 64-bit integer "
            "(random seed)");
  EXPECT_NE(with_seed("0xffffffffffffffffff").find("does not fit in a 64-bit integer"),
            std::string::npos);
  // toml11 sums 0b digits in a signed integer whose place value overflows at the 63rd digit
  // (undefined behaviour, found by the libFuzzer build's UBSan): refused before parsing.
  EXPECT_EQ(with_seed("0b" + std::string(63, '1')),
            "r.toml:5: a binary integer (0b...) of more than 62 digits does not fit in a 64-bit "
            "integer");
  EXPECT_EQ(with_seed("0b" + std::string(62, '1')), "(accepted)");
  EXPECT_EQ(with_seed("9223372036854775807"), "(accepted)");
  EXPECT_EQ(with_seed("0x7fff_ffff_ffff_ffff"), "(accepted)");
  std::string h = kHead;
  h.replace(h.find("7e10"), 4, "1e400");
  EXPECT_EQ(deck_message(h + kLattice),
            "r.toml:7: [material] young_modulus: = 1e400 does not fit in a double (largest "
            "about 1.8e308) (Young modulus E in Pa)");
  h = kHead;
  h.replace(h.find("7e10"), 4, "1.7976931348623157e308");
  EXPECT_EQ(deck_message(h + kLattice), "(accepted)");
  EXPECT_NE(deck_message(std::string(kHead) +
                         "[[stage]]\nkind = \"compress\"\nstress = [1e4, 1e4, 1e999]\n")
                .find("[stage[0] (compress)] stress: = "),
            std::string::npos);
}

TEST(FuzzRegressions, InvalidUtf8IsRefusedBeforeToml11) {
  // toml11 3.7 reports a bad byte inside a string by resetting a location to an iterator of
  // another buffer: a heap-buffer-overflow read (ASan, libFuzzer build). TOML must be UTF-8.
  EXPECT_EQ(deck_message(std::string(kHead) + "[[stage]]\nname = '''multi\n\xff'''\n"),
            "r.toml:13: invalid UTF-8 (byte 0xFF): a deck must be UTF-8 text");
  EXPECT_EQ(deck_message(std::string(kHead) + "[[stage]]\nname = \"\xed\xa0\x80\"\n"),
            "r.toml:12: invalid UTF-8 (byte 0xED): a deck must be UTF-8 text");
  // Well-formed UTF-8 is fine.
  EXPECT_EQ(deck_message(std::string(kHead) + kLattice +
                         "name = \"\xc3\xa9t\xc3\xa9 \xf0\x9f\x98\x80\"\n"),
            "(accepted)");
}

TEST(FuzzRegressions, LargestSampleSeedGivesStageSeedsWithoutOverflow) {
  // The stage seed default [sample] seed + 1000 + index was a signed sum: undefined behaviour
  // for seed near INT64_MAX. Release builds happened to wrap to the right bits, so this case
  // fails only under UBSan (-fsanitize=undefined, the libFuzzer build): it documents the fix.
  std::string h = kHead;
  h.insert(h.find("[material]"), "seed = 9223372036854775807\n");
  const Deck d = parse_deck(h + "[[stage]]\nkind = \"random\"\nphi = 0.3\n"
                                "[[stage]]\nkind = \"ed_gas\"\ncollisions_per_grain = 1\n",
                            "r.toml");
  EXPECT_EQ(std::get<EdGasStage>(d.stages[1].params).seed, 9223372036854775807ULL + 1001ULL);
}

namespace {
/// The InputError message of read_configuration<dim> ("(read)" if it returned).
template <int dim> std::string read_message(const fs::path& p) {
  try {
    read_configuration<dim>(MPI_COMM_SELF, p);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(read)";
}
/// A fresh 3-D seed file in `dir`, changed by `change` (an open read-write HDF5 file).
template <class F> fs::path seed_changed(const fs::path& dir, const std::string& name, F change) {
  const fs::path p = dir / name;
  fuzz::write_seed_file<3>(p, 9, 1);
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const hid_t f = H5Fopen(p.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  change(f);
  H5Fclose(f);
  return p;
}
} // namespace

TEST(FuzzRegressions, HugeDeclaredDatasetsAreRefusedBeforeAllocating) {
  // n_particles = 2^33 with datasets of that shape and no storage (a 17 kB file): the reader
  // allocated 2^33 rows per dataset (tens of GB, minutes of page faults) before any check.
  TempDir tmp;
  const std::int64_t n = std::int64_t{1} << 33;
  const auto p = seed_changed(tmp.path, "huge.h5", [&](hid_t f) {
    for (const auto& d : fuzz::h5m::datasets()) {
      if (d.rfind("/particles/", 0) != 0)
        continue;
      std::vector<hsize_t> dims;
      fuzz::h5m::read_all<double>(f, d, H5T_NATIVE_DOUBLE, &dims);
      dims[0] = static_cast<hsize_t>(n);
      fuzz::h5m::replace_dataset(f, d, dims, d.ends_with("/id") ? H5T_STD_I64LE : H5T_IEEE_F64LE,
                                 H5T_NATIVE_DOUBLE, nullptr);
    }
    fuzz::h5m::set_scalar_attribute(f, "n_particles", H5T_STD_I64LE, n);
  });
  // Refused before any allocation: the peak resident size does not grow by the 64 GiB the
  // datasets declare (nor by 1 GiB), and CPU time (not wall time: load must not fail the test)
  // stays far below the minutes of page faults the bug cost.
  const double cpu0 = cpu_seconds();
  const long rss0_kib = peak_rss_kib();
  const std::string m = read_message<3>(p);
  EXPECT_EQ(m.rfind(p.string() + ": dataset /particles/id declares 68719476736 bytes of data but "
                                 "the file holds 0 for it",
                    0),
            0u)
      << m;
  EXPECT_LT(peak_rss_kib() - rss0_kib, 1024L * 1024L);
  EXPECT_LT(cpu_seconds() - cpu0, 20.0);
  // The same for a fixed-length /deck string declared 1 GiB long.
  const auto q = seed_changed(tmp.path, "deck.h5", [](hid_t f) {
    const hid_t t = H5Tcopy(H5T_C_S1);
    H5Tset_size(t, std::size_t{1} << 30);
    fuzz::h5m::replace_dataset(f, "/deck", {}, t, t, nullptr);
    H5Tclose(t);
  });
  EXPECT_NE(read_message<3>(q).find("dataset /deck declares 1073741824 bytes of data but the file "
                                    "holds 0"),
            std::string::npos);
  // A compressed copy of a dataset is still a valid file: the bound allows for it.
  const auto c = seed_changed(tmp.path, "deflate.h5", [](hid_t f) {
    std::vector<hsize_t> dims;
    auto v = fuzz::h5m::read_all<double>(f, "/particles/velocity", H5T_NATIVE_DOUBLE, &dims);
    const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
    H5Pset_chunk(dcpl, 2, dims.data());
    H5Pset_deflate(dcpl, 9);
    fuzz::h5m::replace_dataset(f, "/particles/velocity", dims, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE,
                               v.data(), dcpl);
    H5Pclose(dcpl);
  });
  EXPECT_EQ(read_message<3>(c), "(read)");
}

TEST(FuzzRegressions, NonFiniteOrFarPositionsAndBadRadiiAreRefused) {
  // Accepted before: a NaN scaled position reached Decomposition::owner_of (a NaN cast to int,
  // undefined behaviour), a zero radius the neighbour grid.
  TempDir tmp;
  auto poke = [&](const char* name, const char* dset, std::size_t k, double v) {
    return seed_changed(tmp.path, name, [&](hid_t f) {
      auto x = fuzz::h5m::read_all<double>(f, dset, H5T_NATIVE_DOUBLE);
      x[k] = v;
      fuzz::h5m::write_all(f, dset, H5T_NATIVE_DOUBLE, x);
    });
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto p = poke("nan.h5", "/particles/scaled_position", 4, nan);
  EXPECT_EQ(read_message<3>(p), p.string() + ": /particles/scaled_position row 1 = nan (need a "
                                             "finite scaled position near [0, 1))");
  p = poke("far.h5", "/particles/scaled_position", 0, 1e300);
  EXPECT_NE(read_message<3>(p).find("scaled_position row 0 = "), std::string::npos);
  p = poke("r0.h5", "/particles/radius", 2, 0.0);
  EXPECT_EQ(read_message<3>(p),
            p.string() + ": /particles/radius row 2 = 0.000000 (need a positive finite radius)");
  p = poke("slightly.h5", "/particles/scaled_position", 3, -1e-9); // between rebuilds: fine
  EXPECT_EQ(read_message<3>(p), "(read)");
}

TEST(FuzzRegressions, TruncatedSuperblockIsRefusedSilently) {
  // Open MPI's I/O layer printed "mca_fbtl_posix_preadv: error in (p)read(v): Invalid
  // argument" for a file cut inside its superblock: HDF5 handed it a garbage offset.
  // The input the fuzzer found: a version-0 superblock cut after 56 bytes, base address
  // 0xffffff, end-of-file address 0xfffffff7ffffffff.
  const unsigned char cut[56] = {
      0x89, 0x48, 0x44, 0x46, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x00, 0x00, 0x08,
      0x08, 0x00, 0x04, 0x00, 0x10, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
      0x00, 0x00, 0x00, 0x00, 0xff, 0xff, 0xff, 0x00, 0x00, 0x00, 0x00, 0x00, 0x01, 0x00,
      0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xff, 0xff, 0xff, 0xf7, 0xff, 0xff, 0xff, 0xff};
  TempDir tmp;
  const fs::path p = tmp.path / "cut.h5";
  fuzz::write_bytes(p, std::string(reinterpret_cast<const char*>(cut), sizeof cut));
  EXPECT_EQ(fuzz::check_h5(p, tmp.path), "");
  EXPECT_EQ(
      read_message<3>(p).rfind(p.string() + ": cannot open as HDF5 (truncated or corrupt?)", 0),
      0u);
}

TEST(FuzzRegressions, CorruptGlobalHeapsAreRefusedBeforeHdf5FollowsThem) {
  // Inside HDF5 1.10.8's H5Aread of a variable-length string attribute these files hung, crashed
  // (SIGSEGV) and allocated 21 GB. The guard (src/io/hdf5_string_guard.cpp) reads the stored
  // heap reference raw and checks the datatype and the global heap collection first. Capped
  // address space: without the guard the third file fails an allocation inside HDF5, whose
  // message is not the one expected here, instead of taking the machine's memory.
  AddressSpaceCap cap(rlim_t{4} << 30);
  TempDir tmp;
  const fs::path dir = granpack::test::source_dir() / "tests/fuzz/hdf5_upstream";
  fuzz::Watchdog watchdog(30.0, [&] { return dir.string(); });
  const std::pair<const char*, const char*> cases[] = {
      {"global_heap_hang.h5",
       "attribute /format: the string (8 bytes, global heap collection at byte 2048, object 1) "
       "is corrupt: object 0 at byte 456 of the collection claims 0 bytes, which is less than "
       "its own header"},
      {"global_heap_segv.h5",
       "attribute /format: the string (8 bytes, global heap collection at byte 2048, object 1) "
       "is corrupt: object 8 at byte 192 of the collection claims 18446742974197923841 bytes, "
       "more than the collection's 4096"},
      {"vlen_string_21GB.h5",
       "attribute /granpack_version: variable-length string of 4294967041-byte characters"}};
  for (const auto& [name, expect] : cases) {
    const fs::path p = dir / name;
    watchdog.begin(p.string());
    const std::string m = read_message<3>(p);
    EXPECT_EQ(m.rfind(p.string() + ": " + expect, 0), 0u) << m;
    // The whole property of the fuzzing: every reader refuses, nothing on stderr.
    EXPECT_EQ(fuzz::check_h5(p, tmp.path), "") << name;
    // As `granpack info` reads it (tests/cli/hdf5_upstream.sh runs one file end to end): all
    // ranks together, every rank refusing with the same message.
    std::string collective = "(accepted)";
    try {
      describe_file(MPI_COMM_WORLD, p);
    } catch (const InputError& e) {
      collective = e.what();
    }
    EXPECT_EQ(collective.rfind(p.string() + ": " + expect, 0), 0u) << collective;
    EXPECT_LT(watchdog.end(), 5.0) << name;
  }
}

TEST(FuzzRegressions, CorruptAttributeMessagesAreRefusedBeforeHdf5DecodesThem) {
  // H5Aexists decodes every attribute message of an object header and trusts their part sizes:
  // the fuzzer's input (a dataspace size of 65 288 in an 80-byte message) made it copy a value
  // from past its buffer (AddressSanitizer: an 8-byte heap over-read in H5O__msg_iterate_real).
  // The guard (src/io/hdf5_header_guard.cpp) walks the header first. Each case changes one
  // field of one attribute message of /parameters in a fresh seed file (version 1 headers, as
  // granpack writes them: the body is version, reserved, name, datatype and dataspace sizes,
  // then the three parts padded to 8 bytes and the value).
  TempDir tmp;
  auto u16 = [](const std::string& b, std::size_t at) {
    return unsigned(static_cast<unsigned char>(b[at])) |
           unsigned(static_cast<unsigned char>(b[at + 1])) << 8;
  };
  auto set16 = [](std::string& b, std::size_t at, unsigned v) {
    b[at] = char(v & 0xFF), b[at + 1] = char(v >> 8);
  };
  auto pad8 = [](std::size_t n) { return (n + 7) / 8 * 8; };
  // Body offset of the attribute message named `name` (its name starts 8 bytes in).
  auto body_of = [](const std::string& b, const std::string& name) {
    const auto at = b.find(name + std::string(1, '\0'));
    EXPECT_NE(at, std::string::npos) << name;
    return at - 8;
  };
  struct Case {
    const char* file;
    const char* attribute;
    std::function<void(std::string&, std::size_t)> change;
    std::string expect;
  };
  const std::vector<Case> cases = {
      {"space_size.h5", "poisson_ratio",
       [&](std::string& b, std::size_t m) { set16(b, m + 6, 0xFF08); },
       "its dataspace (65288 bytes) runs past the message (64 bytes)"},
      {"name_size.h5", "poisson_ratio",
       [&](std::string& b, std::size_t m) { set16(b, m + 2, 0x4000); },
       "its name (16384 bytes) runs past the message (64 bytes)"},
      {"name_nul.h5", "poisson_ratio", [&](std::string& b, std::size_t m) { b[m + 8 + 13] = 'x'; },
       "its name is not 13 characters and a NUL"},
      {"type_size.h5", "poisson_ratio", [&](std::string& b, std::size_t m) { set16(b, m + 4, 8); },
       "datatype of class 1 needs 20 bytes, the message gives it 8"},
      {"points.h5", "stress_target",
       [&](std::string& b, std::size_t m) {
         // The dataspace (version 1: 8 bytes, then the dimensions) of the 3-vector.
         const std::size_t space = m + 8 + pad8(u16(b, m + 2)) + pad8(u16(b, m + 4));
         b[space + 8] = char(0xE8), b[space + 9] = char(0x03); // 3 -> 1000 points
       },
       "its value (1000 points of 8 bytes) runs past the message (24 bytes left)"}};
  for (const auto& c : cases) {
    const fs::path p = tmp.path / c.file;
    fuzz::write_seed_file<3>(p, 9, 1);
    std::string bytes = fuzz::read_bytes(p);
    c.change(bytes, body_of(bytes, c.attribute));
    fuzz::write_bytes(p, bytes);
    const std::string m = read_message<3>(p);
    const std::string head = p.string() + ": attributes of /parameters/: attribute message ";
    EXPECT_EQ(m.rfind(head, 0), 0u) << m;
    // The name is reported when it is intact.
    const bool named = c.expect.rfind("its name", 0) != 0;
    const std::string tail = (named ? " ('" + std::string(c.attribute) + "')" : std::string()) +
                             " is corrupt: " + c.expect;
    EXPECT_NE(m.find(tail), std::string::npos) << m;
    EXPECT_EQ(m.find("('") == std::string::npos, !named) << m;
    EXPECT_EQ(fuzz::check_h5(p, tmp.path), "") << c.file;
  }
}

TEST(FuzzRegressions, AttributeGuardAcceptsEveryHeaderVersionHdf5Writes) {
  // The guard must refuse nothing HDF5 writes: version 1 headers (granpack's files), version 2
  // headers (libver latest, as h5py writes with libver="latest"), with attributes of the
  // classes a user may add (integer and float arrays, fixed and variable strings, enums such as
  // h5py's booleans) and with more attributes than fit compactly (dense storage).
  TempDir tmp;
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  for (const bool latest : {false, true})
    for (const int count : {3, 20}) {
      const fs::path p =
          tmp.path / ("v" + std::to_string(latest ? 2 : 1) + "_" + std::to_string(count) + ".h5");
      const hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
      if (latest)
        H5Pset_libver_bounds(fapl, H5F_LIBVER_LATEST, H5F_LIBVER_LATEST);
      const hid_t f = H5Fcreate(p.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl);
      const hid_t g = H5Gcreate2(f, "g", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
      auto put = [&](const std::string& name, hid_t type, hid_t space, const void* v) {
        const hid_t a = H5Acreate2(g, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT);
        ASSERT_GE(H5Awrite(a, type, v), 0) << name;
        H5Aclose(a);
      };
      const hsize_t three = 3;
      const hid_t scalar = H5Screate(H5S_SCALAR), vector = H5Screate_simple(1, &three, nullptr);
      const double xyz[3] = {1, 2, 3};
      const int ijk[3] = {4, 5, 6};
      const hid_t fixed = H5Tcopy(H5T_C_S1), vlen = H5Tcopy(H5T_C_S1);
      H5Tset_size(fixed, 5);
      H5Tset_size(vlen, H5T_VARIABLE);
      const hid_t boolean = H5Tenum_create(H5T_NATIVE_SCHAR);
      const signed char no = 0, yes = 1;
      H5Tenum_insert(boolean, "FALSE", &no);
      H5Tenum_insert(boolean, "TRUE", &yes);
      const char* text = "variable";
      for (int k = 0; k < count; k += 5) {
        const std::string n = std::to_string(k);
        put("xyz" + n, H5T_NATIVE_DOUBLE, vector, xyz);
        put("ijk" + n, H5T_NATIVE_INT, vector, ijk);
        put("fixed" + n, fixed, scalar, "abcde");
        put("vlen" + n, vlen, scalar, &text);
        put("bool" + n, boolean, scalar, &yes);
      }
      H5Tclose(boolean), H5Tclose(vlen), H5Tclose(fixed), H5Sclose(vector), H5Sclose(scalar);
      ASSERT_GE(H5Fflush(f, H5F_SCOPE_GLOBAL), 0); // the guard reads the bytes on disk
      EXPECT_NO_THROW(h5::check_attribute_messages(p, g, "attributes of /g/")) << p;
      EXPECT_NO_THROW(h5::check_attribute_messages(p, f, "attributes of /")) << p;
      H5Gclose(g), H5Fclose(f), H5Pclose(fapl);
    }
}

// ------------------------------------------------------------------------------------------
// Randomised decks

TEST(FuzzDecks, SeedsBehaveAsDocumented) {
  // The harness is only meaningful if the seeds are what we think: valid decks accepted,
  // tests/decks/bad refused (each with the message its first line expects).
  const auto src = granpack::test::source_dir();
  int good = 0;
  for (const char* dir : {"jobs/decks", "jobs/decks/ci"})
    for (const auto& e : fs::directory_iterator(src / dir))
      if (e.path().extension() == ".toml") {
        EXPECT_EQ(fuzz::check_deck(fuzz::read_bytes(e.path())), "") << e.path();
        EXPECT_NO_THROW(parse_deck(fuzz::read_bytes(e.path()), e.path().string())) << e.path();
        ++good;
      }
  EXPECT_GT(good, 5);
  for (const auto& e : fs::directory_iterator(src / "tests/decks/bad")) {
    const std::string text = fuzz::read_bytes(e.path());
    EXPECT_EQ(fuzz::check_deck(text), "") << e.path();
    EXPECT_THROW(parse_deck(text, "bad.toml"), InputError) << e.path();
  }
}

TEST(FuzzDecks, MutatedDecksAreAcceptedOrRefusedWithAnInputError) {
  const std::uint64_t count = env_count("GRANPACK_FUZZ_DECKS", 2000);
  const auto seeds = fuzz::deck_seeds(granpack::test::source_dir());
  ASSERT_GT(seeds.size(), 20u);
  const int rank = world_rank(), size = world_size();
  std::string current;
  std::uint64_t current_i = 0;
  fuzz::Watchdog watchdog(30.0, [&] {
    const auto p = failure_dir() / ("deck_hang_" + std::to_string(current_i) + ".toml");
    fuzz::write_bytes(p, current);
    return p.string();
  });
  std::int64_t tried = 0, accepted = 0, failed = 0;
  double slowest = 0;
  const char* messages_file = std::getenv("GRANPACK_FUZZ_MESSAGES");
  FILE* messages = messages_file && *messages_file ? std::fopen(messages_file, "w") : nullptr;
  for (std::uint64_t i = static_cast<std::uint64_t>(rank); i < count; i += size) {
    auto rng = input_rng(1, i);
    current = fuzz::mutate_deck(rng, seeds);
    current_i = i;
    watchdog.begin("deck input " + std::to_string(i));
    const std::string verdict = fuzz::check_deck(current);
    slowest = std::max(slowest, watchdog.end());
    ++tried;
    if (verdict.empty()) {
      try {
        parse_deck(current, "fuzz.toml");
        ++accepted;
      } catch (const InputError& e) {
        // GRANPACK_FUZZ_MESSAGES=FILE collects the first line of every refusal, to review
        // their clarity by eye (docs/fuzzing.md).
        if (messages) {
          const std::string m = e.what();
          std::fprintf(messages, "%s\n", m.substr(0, m.find('\n')).substr(0, 300).c_str());
        }
      }
      continue;
    }
    const auto p = failure_dir() / ("deck_" + std::to_string(i) + ".toml");
    fuzz::write_bytes(p, current);
    report(failed, "deck input " + std::to_string(i), p, verdict);
  }
  if (messages)
    std::fclose(messages);
  tried = sum_over_ranks(tried), accepted = sum_over_ranks(accepted);
  failed = sum_over_ranks(failed), slowest = max_over_ranks(slowest);
  if (rank == 0)
    std::printf("[fuzz] decks: %lld mutated inputs tried (seed %llu), %lld accepted, %lld "
                "refused with InputError, %lld violations; slowest %.3f s\n",
                static_cast<long long>(tried), static_cast<unsigned long long>(fuzz_seed()),
                static_cast<long long>(accepted), static_cast<long long>(tried - accepted - failed),
                static_cast<long long>(failed), slowest);
  EXPECT_EQ(failed, 0);
  // Mutations must also reach the validation behind the TOML syntax: some decks survive.
  EXPECT_GT(accepted, tried / 100);
}

// ------------------------------------------------------------------------------------------
// Randomised HDF5 files

TEST(FuzzHdf5, MutatedFilesAreReadOrRefusedWithAnInputError) {
  const std::uint64_t count = env_count("GRANPACK_FUZZ_H5", 300);
  const int rank = world_rank(), size = world_size();
  TempDir tmp;
  // Seeds: small 3-D and 2-D files, and one without contacts.
  const fs::path seed3 = tmp.path / "seed3.h5", seed2 = tmp.path / "seed2.h5",
                 seed0 = tmp.path / "seed0.h5";
  fuzz::write_seed_file<3>(seed3, 9, 1);
  fuzz::write_seed_file<2>(seed2, 7, 2);
  fuzz::write_seed_file<3>(seed0, 1, 3);
  const std::vector<std::string> seeds = {fuzz::read_bytes(seed3), fuzz::read_bytes(seed2),
                                          fuzz::read_bytes(seed0)};
  for (const auto& p : {seed3, seed2, seed0}) {
    // An intact file: read_configuration of the other dimension refuses it, the rest returns.
    EXPECT_EQ(fuzz::check_h5(p, tmp.path), "") << p;
    EXPECT_NO_THROW(read_file_meta(MPI_COMM_SELF, p));
  }

  const fs::path input = tmp.path / "input.h5";
  std::string description;
  std::uint64_t current_i = 0;
  fuzz::Watchdog watchdog(60.0, [&] {
    const auto p = failure_dir() / ("h5_hang_" + std::to_string(current_i) + ".h5");
    std::error_code ec;
    fs::copy_file(input, p, fs::copy_options::overwrite_existing, ec);
    return p.string();
  });
  std::int64_t tried = 0, meta_ok = 0, failed = 0, hdf5_oom = 0;
  double slowest = 0;
  const AddressSpaceCap cap(rlim_t{8} << 30);
  for (std::uint64_t i = static_cast<std::uint64_t>(rank); i < count; i += size) {
    auto rng = input_rng(2, i);
    current_i = i;
    fuzz::write_bytes(input, rng.pick(seeds));
    description.clear();
    const auto how = rng.below(4);
    if (how != 0) // structural (sometimes twice)
      description += fuzz::mutate_h5_structure(input, rng) + "; ";
    if (how == 3)
      description += fuzz::mutate_h5_structure(input, rng) + "; ";
    if (how <= 1) { // bytes
      std::string bytes = fuzz::read_bytes(input);
      description += fuzz::mutate_h5_bytes(bytes, rng);
      fuzz::write_bytes(input, bytes);
    }
    watchdog.begin("HDF5 input " + std::to_string(i) + " (" + description + ")");
    const std::string verdict = fuzz::check_h5(input, tmp.path);
    slowest = std::max(slowest, watchdog.end());
    ++tried;
    try {
      read_file_meta(MPI_COMM_SELF, input);
      ++meta_ok;
    } catch (const std::exception& e) {
      hdf5_oom +=
          std::string(e.what()).find("(HDF5: memory allocation failed") != std::string::npos;
    }
    if (verdict.empty())
      continue;
    const auto p = failure_dir() / ("h5_" + std::to_string(i) + ".h5");
    std::error_code ec;
    fs::copy_file(input, p, fs::copy_options::overwrite_existing, ec);
    report(failed, "HDF5 input " + std::to_string(i) + " [" + description + "]", p, verdict);
  }
  tried = sum_over_ranks(tried), meta_ok = sum_over_ranks(meta_ok);
  failed = sum_over_ranks(failed), slowest = max_over_ranks(slowest);
  hdf5_oom = sum_over_ranks(hdf5_oom);
  if (rank == 0)
    std::printf("[fuzz] HDF5: %lld mutated files tried (seed %llu), %lld with readable "
                "metadata, %lld violations, %lld refused because HDF5 ran into the memory cap; "
                "slowest %.3f s\n",
                static_cast<long long>(tried), static_cast<unsigned long long>(fuzz_seed()),
                static_cast<long long>(meta_ok), static_cast<long long>(failed),
                static_cast<long long>(hdf5_oom), slowest);
  EXPECT_EQ(failed, 0);
  EXPECT_GT(meta_ok, tried / 20); // the mutations are not all caught at the first check
}

// ------------------------------------------------------------------------------------------
// Replaying a saved input: GRANPACK_FUZZ_REPLAY=<file.toml|file.h5> mpi_fuzz_inputs
//   --gtest_filter=FuzzReplay.*   (skipped when the variable is not set)

TEST(FuzzReplay, SavedInput) {
  const char* file = std::getenv("GRANPACK_FUZZ_REPLAY");
  if (!file || !*file)
    GTEST_SKIP() << "GRANPACK_FUZZ_REPLAY is not set";
  const fs::path p = file;
  TempDir tmp;
  const AddressSpaceCap cap(rlim_t{8} << 30);
  fuzz::Watchdog watchdog(600.0, [&] { return p.string(); });
  watchdog.begin("replay of " + p.string());
  const std::string verdict = p.extension() == ".h5"
                                  ? fuzz::check_h5(p, tmp.path)
                                  : fuzz::check_deck(fuzz::read_bytes(p), p.string());
  std::printf("[fuzz] replay of %s took %.3f s\n", p.c_str(), watchdog.end());
  EXPECT_EQ(verdict, "");
}
