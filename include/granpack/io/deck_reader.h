#pragma once
// Reading one TOML table of a deck with validation. Every accessor names, on failure, the
// deck file, the key with its table path, the line, the offending value and what is allowed,
// and throws InputError (exit code 2). finish() rejects keys that were never asked for, so a
// misspelt key is an error instead of a silently ignored setting.
#include <cstdint>
#include <limits>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <toml.hpp>

namespace granpack {

/// Allowed interval of a number; open or closed at each end.
struct Range {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false, hi_open = false;
  static Range positive() { return {0.0, std::numeric_limits<double>::infinity(), true, false}; }
  static Range non_negative() {
    return {0.0, std::numeric_limits<double>::infinity(), false, false};
  }
  static Range closed(double a, double b) { return {a, b, false, false}; }
  static Range half_open(double a, double b) { return {a, b, false, true}; } ///< [a, b)
  static Range open(double a, double b) { return {a, b, true, true}; }
  bool contains(double x) const;
  std::string describe() const;
};

class TableReader {
public:
  /// `table_path` is how the user sees it: "material", "stage[2] (compress)".
  TableReader(const toml::value& table, std::string file, std::string table_path);

  double number(const std::string& key, Range range, const std::string& what);
  double number_or(const std::string& key, double fallback, Range range, const std::string& what);
  std::int64_t integer(const std::string& key, Range range, const std::string& what);
  std::int64_t integer_or(const std::string& key, std::int64_t fallback, Range range,
                          const std::string& what);
  std::string choice(const std::string& key, const std::vector<std::string>& allowed,
                     const std::string& what);
  std::string choice_or(const std::string& key, const std::string& fallback,
                        const std::vector<std::string>& allowed, const std::string& what);
  std::string string_or(const std::string& key, const std::string& fallback,
                        const std::string& what);
  bool boolean_or(const std::string& key, bool fallback, const std::string& what);
  std::vector<std::int64_t> integers(const std::string& key, std::size_t count, Range range,
                                     const std::string& what);
  std::optional<std::vector<std::int64_t>> integers_opt(const std::string& key, std::size_t count,
                                                        Range range, const std::string& what);
  bool has(const std::string& key) const;
  /// Marks a key as known without reading it (it is read elsewhere, e.g. a sub-table).
  void accept(const std::string& key) { known_.insert(key); }
  /// Throws for keys present in the table that no accessor asked for.
  void finish() const;

  [[noreturn]] void fail(const std::string& key, const std::string& problem) const;
  /// A required key is absent: names a similar unknown key of the table if there is one.
  [[noreturn]] void fail_missing(const std::string& key, const std::string& what) const;
  const std::string& file() const { return file_; }
  const std::string& path() const { return path_; }

private:
  const toml::value* find(const std::string& key);
  double to_double(const std::string& key, const toml::value& v, const std::string& what);
  std::string where(const std::string& key) const;

  const toml::value& table_;
  std::string file_, path_;
  std::set<std::string> known_;
};

/// The TOML text of a value, for messages: 0.3, "fcc", [4, 4, 4].
std::string toml_text(const toml::value& v);

/// False if v is a number whose TOML token does not fit the stored type: toml11 3.7 silently
/// clamps an integer beyond 64 bits to INT64_MAX/MIN (binary literals wrap) and a float beyond
/// DBL_MAX to +-DBL_MAX, which would otherwise be accepted as a valid setting.
bool number_is_exact(const toml::value& v);

} // namespace granpack
