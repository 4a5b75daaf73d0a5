#pragma once
// Randomised inputs for the deck parser and the HDF5 configuration reader, and the property
// each must satisfy (docs/fuzzing.md). Header-only so that the ctest case
// (tests/mpi/fuzz_inputs.cpp, normal build) and the libFuzzer drivers (tests/fuzz/, clang
// only, GRANPACK_BUILD_FUZZERS=ON) share one definition of "mutation" and of "correct".
//
// The property, for every input:
//   * the reader returns, or throws granpack::InputError whose message starts with the file
//     name and says something after it (never another exception, never a crash);
//   * it takes bounded time (a Watchdog aborts the process naming the input);
//   * HDF5 reads print nothing on stderr (granpack silences HDF5's error stacks);
//   * what is returned is what the documentation promises (ids >= 0, first < second, finite
//     positive radii, finite positions, row counts equal to the root attributes).
#include <hdf5.h>
#include <mpi.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <mutex>
#include <random>
#include <string>
#include <thread>
#include <typeinfo>
#include <vector>

#include "granpack/core/error.h"
#include "granpack/io/deck.h"
#include "granpack/io/hdf5_store.h"

namespace granpack::fuzz {

namespace fs = std::filesystem;

// -----------------------------------------------------------------------------------------
// Small utilities

class Rng {
public:
  explicit Rng(std::uint64_t seed) : g_(seed) {}
  std::uint64_t u64() { return g_(); }
  /// Uniform in [0, n) (n > 0).
  std::size_t below(std::size_t n) { return n ? static_cast<std::size_t>(g_() % n) : 0; }
  double uniform() { return std::uniform_real_distribution<double>(0, 1)(g_); }
  bool chance(double p) { return uniform() < p; }
  template <class C> const auto& pick(const C& c) { return c[below(c.size())]; }
  /// Log-uniform size in [1, max]: small sizes often, huge ones sometimes.
  std::size_t log_size(std::size_t max) {
    const double x = std::uniform_real_distribution<double>(0, std::log(double(max) + 1))(g_);
    return std::max<std::size_t>(1, static_cast<std::size_t>(std::exp(x)));
  }

private:
  std::mt19937_64 g_;
};

inline std::string read_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}
inline void write_bytes(const fs::path& p, const std::string& bytes) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

/// Aborts the process if one input takes longer than `limit` (a hang), after saving the
/// input for reproduction and saying where it is. One input at a time.
class Watchdog {
public:
  /// `save` writes the current input to disk and returns where (called only on a hang).
  Watchdog(double limit_seconds, std::function<std::string()> save)
      : limit_(limit_seconds), save_(std::move(save)), report_fd_(dup(2)),
        thread_([this] { run(); }) {}
  ~Watchdog() {
    {
      std::lock_guard lock(m_);
      stop_ = true;
    }
    cv_.notify_all();
    thread_.join();
    close(report_fd_);
  }
  /// Starts timing an input.
  void begin(std::string label) {
    std::lock_guard lock(m_);
    label_ = std::move(label);
    start_ = std::chrono::steady_clock::now();
    busy_ = true;
  }
  /// Ends timing; returns the seconds the input took.
  double end() {
    std::lock_guard lock(m_);
    busy_ = false;
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }

private:
  void run() {
    std::unique_lock lock(m_);
    while (!stop_) {
      cv_.wait_for(lock, std::chrono::milliseconds(200));
      if (busy_ &&
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count() >
              limit_) {
        const std::string where = save_ ? save_() : std::string("(not saved)");
        // To the stderr of construction time: check_h5 redirects fd 2 while it runs.
        const std::string msg = "FUZZ HANG: " + label_ + " took more than " +
                                std::to_string(limit_) + " s; input saved as " + where + "\n";
        [[maybe_unused]] auto written = write(report_fd_, msg.data(), msg.size());
        std::abort();
      }
    }
  }
  double limit_;
  std::function<std::string()> save_;
  int report_fd_;
  std::mutex m_;
  std::condition_variable cv_;
  bool stop_ = false, busy_ = false;
  std::string label_;
  std::chrono::steady_clock::time_point start_;
  std::thread thread_;
};

/// "" if f() returned or threw an InputError naming `file`; otherwise what went wrong.
template <class F> std::string expect_input_error(const std::string& file, F&& f) {
  try {
    f();
    return "";
  } catch (const InputError& e) {
    const std::string m = e.what();
    if (m.rfind(file + ":", 0) != 0)
      return "InputError does not start with the file name '" + file + ":': " + m;
    if (m.find_first_not_of(" \n", file.size() + 1) == std::string::npos)
      return "InputError says nothing after the file name: " + m;
    return "";
  } catch (const Error& e) {
    return "granpack::Error (exit code " + std::to_string(e.exit_code()) +
           ") instead of InputError: " + e.what();
  } catch (const std::exception& e) {
    return std::string("escaped ") + typeid(e).name() + ": " + e.what();
  } catch (...) {
    return "escaped an exception not derived from std::exception";
  }
}

/// For the libFuzzer drivers: a violated property must be a crash, so libFuzzer keeps the input.
inline void abort_if_violated(const std::string& verdict) {
  if (verdict.empty())
    return;
  std::fprintf(stderr, "PROPERTY VIOLATED: %s\n", verdict.substr(0, 2000).c_str());
  std::abort();
}

// -----------------------------------------------------------------------------------------
// Decks

/// Every key of docs/deck.md, the table names and the stage kinds: the vocabulary of the
/// structure-aware mutations.
inline const std::vector<std::string>& deck_keys() {
  static const std::vector<std::string> keys = {"dimension",
                                                "n",
                                                "diameter",
                                                "distribution",
                                                "min_diameter_ratio",
                                                "seed",
                                                "density",
                                                "normal_law",
                                                "young_modulus",
                                                "poisson_ratio",
                                                "normal_stiffness",
                                                "tangential_stiffness_ratio",
                                                "friction",
                                                "damping",
                                                "time_step_fraction",
                                                "skin",
                                                "log_every",
                                                "quiet",
                                                "checkpoint_every_steps",
                                                "checkpoint_every_seconds",
                                                "kind",
                                                "name",
                                                "lattice",
                                                "phi",
                                                "cells",
                                                "pressure",
                                                "stress",
                                                "fixed_axes",
                                                "inertia_max",
                                                "cell_mass",
                                                "max_steps",
                                                "quench_interval",
                                                "quench_delay",
                                                "tolerance_force",
                                                "tolerance_stress",
                                                "tolerance_kinetic",
                                                "file",
                                                "collisions_per_grain",
                                                "growth_rate",
                                                "rescale_every",
                                                "report_phi",
                                                "factor",
                                                "count",
                                                "write",
                                                "force",
                                                "tolerance",
                                                "sample",
                                                "material",
                                                "numerics",
                                                "output",
                                                "stage"};
  return keys;
}

inline const std::vector<std::string>& deck_values() {
  static const std::vector<std::string> values = {"0",
                                                  "-0",
                                                  "1",
                                                  "-1",
                                                  "2",
                                                  "3",
                                                  "4",
                                                  "7",
                                                  "1000",
                                                  "9223372036854775807",
                                                  "-9223372036854775808",
                                                  "9223372036854775808",
                                                  "99999999999999999999",
                                                  "-99999999999999999999",
                                                  "0x7fffffffffffffff",
                                                  "0xffffffffffffffffff",
                                                  "0o777777777777777777777777",
                                                  "0b" + std::string(64, '1'),
                                                  "0b" + std::string(70, '1'),
                                                  "1_000",
                                                  "0.0",
                                                  "-0.0",
                                                  "0.5",
                                                  "0.6",
                                                  "0.64",
                                                  "0.74",
                                                  "1.0",
                                                  "1e-3",
                                                  "1e9",
                                                  "1e308",
                                                  "1.7976931348623157e308",
                                                  "1e309",
                                                  "-1e400",
                                                  "1e-320",
                                                  "1e-400",
                                                  "5e-324",
                                                  "inf",
                                                  "+inf",
                                                  "-inf",
                                                  "nan",
                                                  "+nan",
                                                  "-nan",
                                                  "true",
                                                  "false",
                                                  "\"\"",
                                                  "\"fcc\"",
                                                  "\"hex\"",
                                                  "\"hertz\"",
                                                  "\"linear\"",
                                                  "\"uniform\"",
                                                  "\"compress\"",
                                                  "\"lattice\"",
                                                  "\"random\"",
                                                  "\"read\"",
                                                  "\"write\"",
                                                  "\"set\"",
                                                  "\"ed_gas\"",
                                                  "\"ls_compress\"",
                                                  "\"expand\"",
                                                  "\"pressure_steps\"",
                                                  "\"fix_rattlers\"",
                                                  "\"a.h5\"",
                                                  "\"/etc/passwd\"",
                                                  "\"../x.h5\"",
                                                  "\".h5\"",
                                                  "\"\\u00e9\"",
                                                  "\"\\uD800\"",
                                                  "\"\\U0011FFFF\"",
                                                  "\"\\x\"",
                                                  "'literal'",
                                                  "'''multi\nline'''",
                                                  "\"\"\"multi\nline\"\"\"",
                                                  "[]",
                                                  "[1]",
                                                  "[1, 2]",
                                                  "[1, 2, 3]",
                                                  "[4, 4, 4]",
                                                  "[0, 4, 4]",
                                                  "[-1, 4, 4]",
                                                  "[1e6, 1, 1]",
                                                  "[1000000, 1000000, 1000000]",
                                                  "[1.5, 2, 3]",
                                                  "[\"x\"]",
                                                  "[\"x\", \"x\"]",
                                                  "[\"x\", \"y\", \"z\"]",
                                                  "[\"q\"]",
                                                  "[1e4, 1e4, 1e4]",
                                                  "[1e400, 1, 1]",
                                                  "[0.49, 0.58]",
                                                  "[0.58, 0.49]",
                                                  "[nan]",
                                                  "[[1], [2]]",
                                                  "[1, \"a\"]",
                                                  "{}",
                                                  "{a = 1}",
                                                  "{kind = \"set\"}",
                                                  "1979-05-27T07:32:00Z",
                                                  "1979-05-27",
                                                  "07:32:00",
                                                  "07:32:00.999999999",
                                                  "1979-05-27T00:32:00.999999-07:00",
                                                  "9999-99-99",
                                                  "24:61:61"};
  return values;
}

/// Fragments that exercise the TOML lexer: quotes, brackets, escapes, invalid UTF-8, NULs.
inline const std::vector<std::string>& deck_fragments() {
  static const std::vector<std::string> f = {"[",
                                             "]",
                                             "[[",
                                             "]]",
                                             "{",
                                             "}",
                                             "\"",
                                             "'",
                                             "\"\"\"",
                                             "'''",
                                             "=",
                                             "==",
                                             ",",
                                             ".",
                                             "#",
                                             "\n",
                                             "\r\n",
                                             "\r",
                                             "\t",
                                             "\\",
                                             "\\u",
                                             "\\U",
                                             "\xff",
                                             "\xc3",
                                             "\xc0\x80",
                                             "\xed\xa0\x80",
                                             "\xf4\x90\x80\x80",
                                             std::string(1, '\0'),
                                             "\xef\xbb\xbf",
                                             "+",
                                             "-",
                                             "_",
                                             "e",
                                             "E",
                                             "0x",
                                             "0b",
                                             "0o",
                                             "inf",
                                             "nan",
                                             "T",
                                             "Z",
                                             ":",
                                             "[stage]",
                                             "[[stage]]",
                                             "[sample]",
                                             "[sample.x]",
                                             "[[sample]]",
                                             "[material]",
                                             "a.b.c",
                                             "\"a.b\"",
                                             " = "};
  return f;
}

/// The seed decks: every valid deck of jobs/decks and jobs/decks/ci, every bad deck of
/// tests/decks/bad, and the example of docs/deck.md.
inline std::vector<std::string> deck_seeds(const fs::path& source_dir) {
  std::vector<std::string> seeds;
  for (const char* dir : {"jobs/decks", "jobs/decks/ci", "tests/decks/bad"}) {
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(source_dir / dir))
      if (e.path().extension() == ".toml")
        files.push_back(e.path());
    std::sort(files.begin(), files.end()); // directory order is not deterministic
    for (const auto& p : files)
      seeds.push_back(read_bytes(p));
  }
  const std::string doc = read_bytes(source_dir / "docs/deck.md");
  const auto a = doc.find("```toml\n"), b = doc.find("```", a + 8);
  if (a != std::string::npos && b != std::string::npos)
    seeds.push_back(doc.substr(a + 8, b - a - 8));
  return seeds;
}

inline std::vector<std::string> split_lines(const std::string& s) {
  std::vector<std::string> lines;
  std::size_t start = 0;
  while (start <= s.size()) {
    const auto nl = s.find('\n', start);
    if (nl == std::string::npos) {
      if (start < s.size())
        lines.push_back(s.substr(start));
      break;
    }
    lines.push_back(s.substr(start, nl - start));
    start = nl + 1;
  }
  return lines;
}
inline std::string join_lines(const std::vector<std::string>& lines) {
  std::string s;
  for (const auto& l : lines)
    s += l + "\n";
  return s;
}

/// Pathologically nested text: arrays, inline tables, dotted keys or table headers, of a
/// depth from a few to 10^5, sometimes unbalanced.
inline std::string deep_nesting(Rng& rng) {
  const std::size_t d = rng.log_size(100000);
  std::string s;
  switch (rng.below(5)) {
  case 0:
    s = "x = " + std::string(d, '[') + "1" + std::string(rng.chance(0.8) ? d : d / 2, ']');
    break;
  case 1:
    s = "x = ";
    for (std::size_t i = 0; i < d; ++i)
      s += "{a=";
    s += "1";
    for (std::size_t i = 0; i < d; ++i)
      s += "}";
    break;
  case 2:
    s = "a";
    for (std::size_t i = 0; i < d; ++i)
      s += ".a";
    s += " = 1";
    break;
  case 3:
    s = "[sample";
    for (std::size_t i = 0; i < d; ++i)
      s += ".x";
    s += "]";
    break;
  default:
    s = "x = ";
    for (std::size_t i = 0; i < d; ++i)
      s += "[{a=";
    break;
  }
  return s;
}

/// One random edit of a deck; `seeds` supplies lines for splicing.
inline void mutate_deck_once(std::string& text, Rng& rng, const std::vector<std::string>& seeds) {
  auto lines = split_lines(text);
  auto rebuild = [&] { text = join_lines(lines); };
  auto kv_line = [&]() -> long { // index of a random "key = value" line, or -1
    std::vector<std::size_t> idx;
    for (std::size_t i = 0; i < lines.size(); ++i)
      if (lines[i].find('=') != std::string::npos && lines[i][0] != '#')
        idx.push_back(i);
    return idx.empty() ? -1 : static_cast<long>(rng.pick(idx));
  };
  switch (rng.below(16)) {
  case 0: // bit flip
    if (!text.empty())
      text[rng.below(text.size())] ^= static_cast<char>(1u << rng.below(8));
    break;
  case 1: // random byte
    if (!text.empty())
      text[rng.below(text.size())] = static_cast<char>(rng.below(256));
    break;
  case 2: // insert a lexer fragment
    text.insert(rng.below(text.size() + 1), rng.pick(deck_fragments()));
    break;
  case 3: { // delete a range
    if (text.empty())
      break;
    const auto at = rng.below(text.size());
    text.erase(at, rng.log_size(text.size() - at));
    break;
  }
  case 4: // truncate
    text.resize(rng.below(text.size() + 1));
    break;
  case 5: { // delete, duplicate or swap lines (duplicate keys and tables)
    if (lines.empty())
      break;
    const auto i = rng.below(lines.size()), j = rng.below(lines.size());
    const auto op = rng.below(3);
    if (op == 0)
      lines.erase(lines.begin() + static_cast<long>(i));
    else if (op == 1)
      lines.insert(lines.begin() + static_cast<long>(j), lines[i]);
    else
      std::swap(lines[i], lines[j]);
    rebuild();
    break;
  }
  case 6:
  case 7: { // replace a value by an interesting one (type changes, overflow, NaN, inf, ...)
    const long i = kv_line();
    if (i < 0)
      break;
    auto& l = lines[static_cast<std::size_t>(i)];
    l = l.substr(0, l.find('=') + 1) + " " + rng.pick(deck_values());
    rebuild();
    break;
  }
  case 8: { // replace a key by another real key (wrong table, duplicate, misplaced)
    const long i = kv_line();
    if (i < 0)
      break;
    auto& l = lines[static_cast<std::size_t>(i)];
    l = rng.pick(deck_keys()) + " " + l.substr(l.find('='));
    rebuild();
    break;
  }
  case 9: { // insert a new key = value line
    lines.insert(lines.begin() + static_cast<long>(rng.below(lines.size() + 1)),
                 rng.pick(deck_keys()) + " = " + rng.pick(deck_values()));
    rebuild();
    break;
  }
  case 10: { // a table header: new, changed, duplicated block
    const auto& k = rng.pick(deck_keys());
    const std::vector<std::string> headers = {
        "[" + k + "]", "[[" + k + "]]",      "[stage]",
        "[[stage]]",   "[sample." + k + "]", "[[stage." + k + "]]"};
    lines.insert(lines.begin() + static_cast<long>(rng.below(lines.size() + 1)), rng.pick(headers));
    rebuild();
    break;
  }
  case 11: { // duplicate a whole table block
    std::vector<std::size_t> heads;
    for (std::size_t i = 0; i < lines.size(); ++i)
      if (!lines[i].empty() && lines[i][0] == '[')
        heads.push_back(i);
    if (heads.empty())
      break;
    const auto h = rng.pick(heads);
    auto e = h + 1;
    while (e < lines.size() && (lines[e].empty() || lines[e][0] != '['))
      ++e;
    std::vector<std::string> block(lines.begin() + static_cast<long>(h),
                                   lines.begin() + static_cast<long>(e));
    lines.insert(lines.end(), block.begin(), block.end());
    rebuild();
    break;
  }
  case 12: // deep nesting
    lines.insert(lines.begin() + static_cast<long>(rng.below(lines.size() + 1)), deep_nesting(rng));
    rebuild();
    break;
  case 13: { // splice lines of another seed
    const auto other = split_lines(rng.pick(seeds));
    if (other.empty())
      break;
    const auto a = rng.below(other.size()), n = rng.log_size(other.size() - a);
    lines.insert(lines.begin() + static_cast<long>(rng.below(lines.size() + 1)),
                 other.begin() + static_cast<long>(a), other.begin() + static_cast<long>(a + n));
    rebuild();
    break;
  }
  case 14: { // something huge: a long key, string, number or comment
    const std::size_t len = rng.log_size(1 << 17); // toml11 reads about 1 MB/s
    const std::vector<std::string> huge = {
        std::string(len, 'k') + " = 1", "name = \"" + std::string(len, 'x') + "\"",
        "n = " + std::string(len, '9'), "phi = 0." + std::string(len, '5'),
        "# " + std::string(len, '#'),   "x = [" + std::string(len, '1') + "]"};
    lines.insert(lines.begin() + static_cast<long>(rng.below(lines.size() + 1)), rng.pick(huge));
    rebuild();
    break;
  }
  default: { // whole-text transformations
    const auto op = rng.below(4);
    if (op == 0)
      text.clear();
    else if (op == 1)
      text = "\xef\xbb\xbf" + text;
    else if (op == 2) {
      std::string crlf;
      for (char c : text)
        crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
      text = crlf;
    } else {
      text += text; // every table and key twice
    }
    break;
  }
  }
}

/// A mutated deck: a random seed with 1 to 4 edits.
inline std::string mutate_deck(Rng& rng, const std::vector<std::string>& seeds) {
  std::string text = rng.pick(seeds);
  const std::size_t edits = 1 + rng.below(4);
  for (std::size_t k = 0; k < edits; ++k)
    mutate_deck_once(text, rng, seeds);
  return text;
}

/// The property for one deck: "" if it holds, else the violation. A message "FILE:LINE: ..."
/// must name a line that exists.
inline std::string check_deck(const std::string& text, const std::string& file = "fuzz.toml") {
  std::string line_problem;
  std::string verdict = expect_input_error(file, [&] {
    try {
      parse_deck(text, file);
    } catch (const InputError& e) {
      const std::string m = e.what();
      const auto rest = m.substr(file.size() + 1);
      std::size_t digits = 0;
      while (digits < rest.size() && std::isdigit(static_cast<unsigned char>(rest[digits])))
        ++digits;
      if (m.rfind(file + ":", 0) == 0 && digits > 0 && digits < 12 && rest[digits] == ':') {
        const long line = std::stol(rest.substr(0, digits));
        const long lines = 1 + static_cast<long>(std::count(text.begin(), text.end(), '\n'));
        if (line < 1 || line > lines)
          line_problem = "message names line " + std::to_string(line) + " of a " +
                         std::to_string(lines) + "-line deck: " + m;
      }
      throw;
    }
  });
  return verdict.empty() ? line_problem : verdict;
}

// -----------------------------------------------------------------------------------------
// HDF5 configurations

/// A small valid configuration (n grains on a jittered grid, a few contacts), written with
/// write_configuration on MPI_COMM_SELF.
template <int dim> void write_seed_file(const fs::path& path, int n, std::uint64_t seed) {
  Rng rng(seed);
  Configuration<dim> c;
  for (int a = 0; a < dim; ++a) {
    c.cell.length[a] = 1e-2 * (1 + 0.1 * a);
    c.cell.rate[a] = -1e-6 * a;
  }
  for (int i = 0; i < n; ++i) {
    Particle<dim> q;
    q.id = 3 * i + 1; // not contiguous, as the format allows
    q.radius = 5e-4 * (0.8 + 0.2 * rng.uniform());
    q.mass = 1e-6, q.inertia = 1e-13;
    for (int a = 0; a < dim; ++a)
      q.position[a] = rng.uniform(), q.velocity[a] = rng.uniform() - 0.5;
    c.particles.add_owned(q);
  }
  for (int k = 0; k + 1 < n; k += 2) {
    ContactState<dim> s;
    s.normal_force = 1e-3 * (k + 1);
    s.tangential_force.setConstant(1e-5);
    s.flags = static_cast<std::uint32_t>(k % 8);
    s.age = k;
    c.contacts.insert({3 * k + 1, 3 * (k + 1) + 1}, s);
  }
  c.meta.stage_name = "seed";
  c.meta.deck_text = "[sample]\ndimension = " + std::to_string(dim) + "\n";
  StateParameters params; // so that the reader of /parameters is fuzzed too
  params.contact_law.young_modulus = 7e10;
  params.contact_law.poisson_ratio = 0.3;
  params.contact_law.friction = 0.3;
  params.stress_target =
      StressTarget{2, std::vector<double>(dim, 1e4), std::vector<bool>(dim, false), 1e4};
  c.meta.parameters = params;
  write_configuration<dim>(MPI_COMM_SELF, path, c);
}

namespace h5m { // structural mutations through the HDF5 C API (serial, default driver)

inline const std::vector<std::string>& datasets() {
  static const std::vector<std::string> d = {"/deck",
                                             "/cell/length",
                                             "/cell/rate",
                                             "/particles/id",
                                             "/particles/radius",
                                             "/particles/mass",
                                             "/particles/inertia",
                                             "/particles/scaled_position",
                                             "/particles/position",
                                             "/particles/velocity",
                                             "/particles/angular_velocity",
                                             "/particles/orientation",
                                             "/contacts/first",
                                             "/contacts/second",
                                             "/contacts/normal_force",
                                             "/contacts/tangential_force",
                                             "/contacts/rolling",
                                             "/contacts/flags",
                                             "/contacts/age"};
  return d;
}
inline const std::vector<std::string>& root_attributes() {
  static const std::vector<std::string> a = {
      "format", "format_version", "granpack_version", "dimension",  "n_particles", "n_contacts",
      "time",   "step",           "stage_index",      "stage_name", "kind"};
  return a;
}

inline void replace_attribute(hid_t obj, const char* name, hid_t type, hid_t space,
                              const void* data) {
  if (H5Aexists(obj, name) > 0)
    H5Adelete(obj, name);
  const hid_t a = H5Acreate2(obj, name, type, space, H5P_DEFAULT, H5P_DEFAULT);
  if (a >= 0) {
    if (data)
      H5Awrite(a, type, data);
    H5Aclose(a);
  }
}
template <class T> void set_scalar_attribute(hid_t obj, const char* name, hid_t type, T v) {
  const hid_t s = H5Screate(H5S_SCALAR);
  replace_attribute(obj, name, type, s, &v);
  H5Sclose(s);
}
inline void set_string_attribute(hid_t obj, const char* name, const std::string& v) {
  const hid_t t = H5Tcopy(H5T_C_S1);
  H5Tset_size(t, std::max<std::size_t>(v.size(), 1));
  const hid_t s = H5Screate(H5S_SCALAR);
  std::string padded = v.empty() ? std::string(1, '\0') : v;
  replace_attribute(obj, name, t, s, padded.data());
  H5Sclose(s);
  H5Tclose(t);
}

/// Reads a whole dataset as doubles (or int64), converted by HDF5; empty if it fails.
template <class T>
std::vector<T> read_all(hid_t file, const std::string& path, hid_t mtype,
                        std::vector<hsize_t>* dims_out = nullptr) {
  std::vector<T> v;
  const hid_t d = H5Dopen2(file, path.c_str(), H5P_DEFAULT);
  if (d < 0)
    return v;
  const hid_t s = H5Dget_space(d);
  const hssize_t n = H5Sget_simple_extent_npoints(s);
  if (dims_out) {
    dims_out->assign(static_cast<std::size_t>(std::max(H5Sget_simple_extent_ndims(s), 0)), 0);
    H5Sget_simple_extent_dims(s, dims_out->data(), nullptr);
  }
  if (n > 0 && n < (1 << 20)) {
    v.resize(static_cast<std::size_t>(n));
    if (H5Dread(d, mtype, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()) < 0)
      v.clear();
  }
  H5Sclose(s);
  H5Dclose(d);
  return v;
}
template <class T>
void write_all(hid_t file, const std::string& path, hid_t mtype, const std::vector<T>& v) {
  const hid_t d = H5Dopen2(file, path.c_str(), H5P_DEFAULT);
  if (d < 0)
    return;
  H5Dwrite(d, mtype, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
  H5Dclose(d);
}

/// Replaces a dataset by a new one of the given shape and file type, holding `data` if it is
/// given (else left unwritten: no storage is allocated, a read returns the fill value).
inline void replace_dataset(hid_t file, const std::string& path, const std::vector<hsize_t>& dims,
                            hid_t ftype, hid_t mtype, const void* data, hid_t dcpl = H5P_DEFAULT) {
  H5Ldelete(file, path.c_str(), H5P_DEFAULT);
  const hid_t s = dims.empty()
                      ? H5Screate(H5S_SCALAR)
                      : H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr);
  const hid_t d = H5Dcreate2(file, path.c_str(), ftype, s, H5P_DEFAULT, dcpl, H5P_DEFAULT);
  if (d >= 0) {
    if (data)
      H5Dwrite(d, mtype, H5S_ALL, H5S_ALL, H5P_DEFAULT, data);
    H5Dclose(d);
  }
  H5Sclose(s);
}

inline double interesting_double(Rng& rng) {
  const double v[] = {std::numeric_limits<double>::quiet_NaN(),
                      std::numeric_limits<double>::infinity(),
                      -std::numeric_limits<double>::infinity(),
                      0.0,
                      -0.0,
                      -1.0,
                      1.0,
                      1e300,
                      -1e300,
                      5e-324,
                      1.0 - 1e-17,
                      2.0,
                      -0.5};
  return v[rng.below(std::size(v))];
}
inline std::int64_t interesting_int(Rng& rng) {
  const std::int64_t v[] = {0,
                            -1,
                            1,
                            2,
                            3,
                            4,
                            7,
                            std::numeric_limits<std::int64_t>::max(),
                            std::numeric_limits<std::int64_t>::min(),
                            std::int64_t{1} << 33,
                            std::int64_t{1} << 40,
                            std::int64_t{1} << 62,
                            1000,
                            4000};
  return v[rng.below(std::size(v))];
}

} // namespace h5m

/// One structural mutation of a granpack file (opened read-write with serial HDF5).
/// Returns a short description of what was done, for reports.
inline std::string mutate_h5_structure(const fs::path& path, Rng& rng) {
  using namespace h5m;
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); // the mutator's own failures are expected
  const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  if (f < 0)
    return "open failed";
  std::string did;
  const std::string& ds = rng.pick(datasets());
  const std::string& at = rng.pick(root_attributes());
  std::vector<hsize_t> dims;
  switch (rng.below(18)) {
  case 0:
    H5Ldelete(f, ds.c_str(), H5P_DEFAULT);
    did = "delete " + ds;
    break;
  case 1:
    H5Adelete(f, at.c_str());
    did = "delete attribute " + at;
    break;
  case 2: { // attribute of another type or shape
    did = "retype attribute " + at;
    switch (rng.below(5)) {
    case 0:
      set_scalar_attribute(f, at.c_str(), H5T_IEEE_F64LE, 2.5);
      break;
    case 1:
      set_scalar_attribute(f, at.c_str(), H5T_STD_I64LE, interesting_int(rng));
      break;
    case 2:
      set_string_attribute(f, at.c_str(), rng.chance(0.5) ? "3" : "");
      break;
    case 3: { // an array attribute
      const hsize_t n = 3;
      const hid_t s = H5Screate_simple(1, &n, nullptr);
      const std::int64_t v[3] = {3, 3, 3};
      replace_attribute(f, at.c_str(), H5T_STD_I64LE, s, v);
      H5Sclose(s);
      break;
    }
    default: { // a null dataspace (no value at all)
      const hid_t s = H5Screate(H5S_NULL);
      replace_attribute(f, at.c_str(), H5T_STD_I32LE, s, nullptr);
      H5Sclose(s);
    }
    }
    break;
  }
  case 3: { // counts that disagree with the datasets
    const char* which = rng.chance(0.5) ? "n_particles" : "n_contacts";
    const std::int64_t v = interesting_int(rng);
    set_scalar_attribute(f, which, H5T_STD_I64LE, v);
    did = std::string(which) + " = " + std::to_string(v);
    break;
  }
  case 4: { // dimension, version, format, kind
    switch (rng.below(4)) {
    case 0:
      set_scalar_attribute(f, "dimension", H5T_STD_I32LE, static_cast<int>(rng.below(6)) - 1);
      break;
    case 1:
      set_scalar_attribute(f, "format_version", H5T_STD_I32LE, static_cast<int>(rng.below(4)) - 1);
      break;
    case 2:
      set_string_attribute(f, "format", rng.chance(0.5) ? "granpack2" : "");
      break;
    default:
      set_string_attribute(f, "kind", "frobnicated");
      break;
    }
    did = "root attribute values";
    break;
  }
  case 5: { // a dataset of another shape
    auto v = read_all<double>(f, ds, H5T_NATIVE_DOUBLE, &dims);
    if (dims.empty())
      dims = {1};
    switch (rng.below(4)) {
    case 0:
      dims[0] = dims[0] + 1;
      break;
    case 1:
      dims[0] = dims[0] > 0 ? dims[0] - 1 : 0;
      break;
    case 2:
      dims.push_back(2);
      break;
    default:
      dims.pop_back();
      break;
    }
    hsize_t total = 1;
    for (auto d : dims)
      total *= d;
    v.assign(static_cast<std::size_t>(total), 0.25);
    replace_dataset(f, ds, dims, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, v.data());
    did = "reshape " + ds;
    break;
  }
  case 6: { // a dataset of another type, same shape
    auto v = read_all<double>(f, ds, H5T_NATIVE_DOUBLE, &dims);
    const hid_t types[] = {H5T_STD_I32LE, H5T_STD_U8LE,   H5T_IEEE_F32BE,
                           H5T_STD_I64BE, H5T_IEEE_F64LE, H5T_STD_U64LE};
    const hid_t t = types[rng.below(std::size(types))];
    replace_dataset(f, ds, dims, t, H5T_NATIVE_DOUBLE, v.empty() ? nullptr : v.data());
    did = "retype " + ds;
    break;
  }
  case 7: { // bad values in the particle and contact data
    did = "values";
    if (rng.chance(0.3)) {
      auto id = read_all<std::int64_t>(f, "/particles/id", H5T_NATIVE_INT64);
      if (!id.empty()) {
        id[rng.below(id.size())] =
            rng.chance(0.5) ? -1 : id[rng.below(id.size())]; // negative or duplicate
        write_all(f, "/particles/id", H5T_NATIVE_INT64, id);
        did = "particle id negative or duplicate";
      }
    } else if (rng.chance(0.4)) {
      auto a = read_all<std::int64_t>(f, "/contacts/first", H5T_NATIVE_INT64);
      auto b = read_all<std::int64_t>(f, "/contacts/second", H5T_NATIVE_INT64);
      if (!a.empty() && a.size() == b.size()) {
        const auto k = rng.below(a.size());
        switch (rng.below(4)) {
        case 0:
          std::swap(a[k], b[k]);
          break; // first > second
        case 1:
          b[k] = a[k];
          break; // first == second
        case 2:
          a[k] = -5;
          break; // negative
        default:
          a[k] = a[0], b[k] = b[0];
          break; // duplicate pair
        }
        write_all(f, "/contacts/first", H5T_NATIVE_INT64, a);
        write_all(f, "/contacts/second", H5T_NATIVE_INT64, b);
        did = "contact keys";
      }
    } else {
      const std::string& d = rng.pick(datasets());
      auto v = read_all<double>(f, d, H5T_NATIVE_DOUBLE);
      if (!v.empty() && d != "/deck") {
        v[rng.below(v.size())] = interesting_double(rng);
        write_all(f, d, H5T_NATIVE_DOUBLE, v);
        did = "value in " + d;
      }
    }
    break;
  }
  case 8: { // huge declared sizes without storage: the reader must not allocate them
    const std::int64_t n = std::int64_t{1} << (30 + rng.below(14));
    set_scalar_attribute(f, rng.chance(0.7) ? "n_particles" : "n_contacts", H5T_STD_I64LE, n);
    const bool particles = rng.chance(0.5);
    for (const auto& d : datasets()) {
      if (d.rfind(particles ? "/particles/" : "/contacts/", 0) != 0)
        continue;
      read_all<double>(f, d, H5T_NATIVE_DOUBLE, &dims);
      if (dims.empty())
        continue;
      dims[0] = static_cast<hsize_t>(n);
      const bool integer =
          d.ends_with("/id") || d.ends_with("first") || d.ends_with("second") || d.ends_with("age");
      replace_dataset(f, d, dims, integer ? H5T_STD_I64LE : H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE,
                      nullptr);
    }
    set_scalar_attribute(f, particles ? "n_particles" : "n_contacts", H5T_STD_I64LE, n);
    did = std::string("huge unallocated ") + (particles ? "particles" : "contacts");
    break;
  }
  case 9: { // /deck of another kind: variable-length, huge fixed-length, integer, array
    did = "/deck variant";
    switch (rng.below(4)) {
    case 0: {
      const hid_t t = H5Tcopy(H5T_C_S1);
      H5Tset_size(t, H5T_VARIABLE);
      const char* text = "[sample]\n";
      replace_dataset(f, "/deck", {}, t, t, &text);
      H5Tclose(t);
      break;
    }
    case 1: {
      const hid_t t = H5Tcopy(H5T_C_S1);
      H5Tset_size(t, std::size_t{1} << (20 + rng.below(12))); // up to 2 GB, never written
      replace_dataset(f, "/deck", {}, t, t, nullptr);
      H5Tclose(t);
      break;
    }
    case 2: {
      const int v = 7;
      replace_dataset(f, "/deck", {}, H5T_STD_I32LE, H5T_NATIVE_INT, &v);
      break;
    }
    default: {
      const hid_t t = H5Tcopy(H5T_C_S1);
      H5Tset_size(t, 4);
      const char text[8] = {'a', 'b', 'c', 'd', 'e', 'f', 'g', 'h'};
      replace_dataset(f, "/deck", {2}, t, t, text);
      H5Tclose(t);
    }
    }
    break;
  }
  case 10: { // a group replaced by a dataset, or a dataset by a group
    const char* groups[] = {"/cell", "/particles", "/contacts"};
    const char* g = groups[rng.below(3)];
    if (rng.chance(0.5)) {
      H5Ldelete(f, g, H5P_DEFAULT);
      const double v = 1;
      replace_dataset(f, g, {1}, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &v);
      did = std::string("group ") + g + " -> dataset";
    } else {
      H5Ldelete(f, ds.c_str(), H5P_DEFAULT);
      const hid_t gg = H5Gcreate2(f, ds.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
      if (gg >= 0)
        H5Gclose(gg);
      did = "dataset " + ds + " -> group";
    }
    break;
  }
  case 11: { // links: dangling, self-referencing, aliasing, external
    H5Ldelete(f, ds.c_str(), H5P_DEFAULT);
    switch (rng.below(4)) {
    case 0:
      H5Lcreate_soft("/nowhere", f, ds.c_str(), H5P_DEFAULT, H5P_DEFAULT);
      break;
    case 1:
      H5Lcreate_soft(ds.c_str(), f, ds.c_str(), H5P_DEFAULT, H5P_DEFAULT);
      break;
    case 2:
      H5Lcreate_soft(rng.pick(datasets()).c_str(), f, ds.c_str(), H5P_DEFAULT, H5P_DEFAULT);
      break;
    default:
      H5Lcreate_external(rng.chance(0.5) ? "/nonexistent.h5" : path.filename().c_str(), ds.c_str(),
                         f, ds.c_str(), H5P_DEFAULT, H5P_DEFAULT);
    }
    did = "link in place of " + ds;
    break;
  }
  case 12: { // a chunked, compressed copy of a dataset: still a valid file
    auto v = read_all<double>(f, ds, H5T_NATIVE_DOUBLE, &dims);
    if (!v.empty() && !dims.empty() && ds != "/deck") {
      const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
      std::vector<hsize_t> chunk = dims;
      chunk[0] = std::max<hsize_t>(1, dims[0] / 2);
      H5Pset_chunk(dcpl, static_cast<int>(chunk.size()), chunk.data());
      H5Pset_deflate(dcpl, 6);
      const bool integer = ds.ends_with("/id") || ds.ends_with("first") || ds.ends_with("second") ||
                           ds.ends_with("age");
      const bool flags = ds.ends_with("flags");
      replace_dataset(f, ds, dims,
                      integer ? H5T_STD_I64LE
                      : flags ? H5T_STD_U32LE
                              : H5T_IEEE_F64LE,
                      H5T_NATIVE_DOUBLE, v.data(), dcpl);
      H5Pclose(dcpl);
      did = "compress " + ds;
    }
    break;
  }
  case 13: { // a dataset declared much larger than its data (unallocated, late allocation)
    read_all<double>(f, ds, H5T_NATIVE_DOUBLE, &dims);
    if (dims.empty())
      dims = {1};
    dims[0] = static_cast<hsize_t>(1) << (20 + rng.below(20));
    replace_dataset(f, ds, dims, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, nullptr);
    did = "huge unallocated " + ds;
    break;
  }
  case 14: { // NaN / out-of-cell positions, non-positive radii (crash material downstream)
    const char* d = rng.chance(0.6) ? "/particles/scaled_position" : "/particles/radius";
    auto v = read_all<double>(f, d, H5T_NATIVE_DOUBLE);
    if (!v.empty()) {
      v[rng.below(v.size())] = interesting_double(rng);
      write_all(f, d, H5T_NATIVE_DOUBLE, v);
    }
    did = std::string("bad value in ") + d;
    break;
  }
  case 15: { // cell lengths
    std::vector<double> v(3, interesting_double(rng));
    write_all(f, "/cell/length", H5T_NATIVE_DOUBLE, v);
    did = "cell length";
    break;
  }
  case 16: { // a huge scalar string attribute type
    const hid_t t = H5Tcopy(H5T_C_S1);
    H5Tset_size(t, std::size_t{1} << (10 + rng.below(8)));
    const hid_t s = H5Screate(H5S_SCALAR);
    std::string text(std::size_t{1} << 17, 'g');
    replace_attribute(f, rng.chance(0.5) ? "stage_name" : "granpack_version", t, s, text.data());
    H5Sclose(s);
    H5Tclose(t);
    did = "long string attribute";
    break;
  }
  default: { // a scalar where an array is expected, or the reverse
    const double v = 1.0;
    replace_dataset(f, ds, {}, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &v);
    did = "scalar " + ds;
    break;
  }
  }
  H5Fclose(f);
  return did;
}

/// Byte-level damage: bit flips (most in the metadata near the start and the end, where
/// superblock, object headers and B-trees live), 8-byte overwrites with extreme values,
/// truncation, appended garbage, zeroed blocks.
inline std::string mutate_h5_bytes(std::string& bytes, Rng& rng) {
  if (bytes.empty())
    return "empty";
  auto offset = [&] {
    const std::size_t n = bytes.size();
    const auto r = rng.below(4);
    if (r == 0)
      return rng.below(std::min<std::size_t>(n, 1024));
    if (r == 1)
      return n - 1 - rng.below(std::min<std::size_t>(n, 4096));
    return rng.below(n);
  };
  const std::size_t edits = 1 + rng.below(6);
  std::string did;
  for (std::size_t k = 0; k < edits; ++k) {
    switch (rng.below(7)) {
    case 0:
    case 1:
    case 2:
      bytes[offset()] ^= static_cast<char>(1u << rng.below(8));
      did += "flip ";
      break;
    case 3: {
      const auto at = offset();
      const std::uint64_t vals[] = {~std::uint64_t{0}, 0, std::uint64_t{1} << 40, rng.u64(),
                                    0x7fffffffffffffffULL};
      const std::uint64_t v = vals[rng.below(std::size(vals))];
      for (std::size_t b = 0; b < 8 && at + b < bytes.size(); ++b)
        bytes[at + b] = static_cast<char>((v >> (8 * b)) & 0xff);
      did += "word ";
      break;
    }
    case 4:
      bytes.resize(std::max<std::size_t>(1, offset()));
      did += "truncate ";
      break;
    case 5:
      bytes += std::string(rng.log_size(4096), static_cast<char>(rng.below(256)));
      did += "append ";
      break;
    default: {
      const auto at = offset();
      const auto len = std::min(bytes.size() - at, rng.log_size(512));
      std::fill(bytes.begin() + static_cast<long>(at), bytes.begin() + static_cast<long>(at + len),
                '\0');
      did += "zero ";
      break;
    }
    }
  }
  return did;
}

/// Redirects stderr to a file while alive; text() is what was written meanwhile.
class StderrCapture {
public:
  explicit StderrCapture(const fs::path& file) : file_(file) {
    std::fflush(stderr);
    saved_ = dup(2);
    FILE* f = std::fopen(file.c_str(), "w");
    if (f) {
      dup2(fileno(f), 2);
      std::fclose(f);
    }
  }
  std::string text() {
    restore();
    return read_bytes(file_);
  }
  ~StderrCapture() { restore(); }

private:
  void restore() {
    if (saved_ < 0)
      return;
    std::fflush(stderr);
    dup2(saved_, 2);
    close(saved_);
    saved_ = -1;
  }
  fs::path file_;
  int saved_ = -1;
};

/// What read_configuration promises about what it returns (docs/hdf5-schema.md).
template <int dim> std::string check_returned(const Configuration<dim>& c) {
  const auto& p = c.particles;
  if (static_cast<std::int64_t>(p.n_owned()) != c.meta.n_particles)
    return "returned " + std::to_string(p.n_owned()) +
           " particles, n_particles = " + std::to_string(c.meta.n_particles);
  if (static_cast<std::int64_t>(c.contacts.size()) != c.meta.n_contacts)
    return "returned " + std::to_string(c.contacts.size()) +
           " contacts, n_contacts = " + std::to_string(c.meta.n_contacts);
  for (int a = 0; a < dim; ++a)
    if (!(c.cell.length[a] > 0) || !std::isfinite(c.cell.length[a]))
      return "returned a non-positive or non-finite cell length";
  for (std::size_t i = 0; i < p.n_owned(); ++i) {
    if (p.id[i] < 0)
      return "returned a negative id";
    if (!(p.radius[i] > 0) || !std::isfinite(p.radius[i]))
      return "returned a non-positive or non-finite radius";
    for (int a = 0; a < dim; ++a)
      if (!std::isfinite(p.position[i][a]))
        return "returned a non-finite scaled position";
  }
  std::vector<std::int64_t> ids(p.id.begin(),
                                p.id.begin() + static_cast<std::ptrdiff_t>(p.n_owned()));
  std::sort(ids.begin(), ids.end());
  if (std::adjacent_find(ids.begin(), ids.end()) != ids.end())
    return "returned a duplicate id";
  for (std::size_t i = 0; i < p.n_owned(); ++i)
    if (!(p.mass[i] > 0) || !std::isfinite(p.mass[i]) || !p.velocity[i].allFinite())
      return "returned a non-positive mass or a non-finite velocity";
  for (std::size_t k = 0; k < c.contacts.size(); ++k) {
    const auto& key = c.contacts.key(k);
    if (key.first < 0 || key.first >= key.second)
      return "returned a contact key with first >= second or negative";
    if (!std::binary_search(ids.begin(), ids.end(), key.first) ||
        !std::binary_search(ids.begin(), ids.end(), key.second))
      return "returned a contact naming a grain the file does not hold";
    const double n = c.contacts.state(k).normal_force;
    if (!(n >= 0) || !std::isfinite(n))
      return "returned a negative or non-finite normal force";
  }
  return "";
}

/// The property for one file: "" if it holds, else the violation(s). `scratch` holds the
/// stderr capture.
inline std::string check_h5(const fs::path& file, const fs::path& scratch) {
  const std::string name = file.string();
  std::string problems;
  auto note = [&](const char* call, const std::string& p) {
    if (!p.empty())
      problems += std::string(problems.empty() ? "" : "; ") + call + ": " + p;
  };
  StderrCapture capture(scratch / "stderr.txt");
  note("read_file_meta", expect_input_error(name, [&] { read_file_meta(MPI_COMM_SELF, file); }));
  note("describe_file", expect_input_error(name, [&] { describe_file(MPI_COMM_SELF, file); }));
  std::string returned;
  note("read_configuration<3>", expect_input_error(name, [&] {
         returned = check_returned(read_configuration<3>(MPI_COMM_SELF, file));
       }));
  note("read_configuration<3> result", returned);
  returned.clear();
  note("read_configuration<2>", expect_input_error(name, [&] {
         returned = check_returned(read_configuration<2>(MPI_COMM_SELF, file));
       }));
  note("read_configuration<2> result", returned);
  const std::string err = capture.text();
  if (!err.empty())
    note("stderr", "the reader printed: " + err.substr(0, 400));
  return problems;
}

} // namespace granpack::fuzz
