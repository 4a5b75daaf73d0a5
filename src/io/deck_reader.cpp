#include "granpack/io/deck_reader.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <sstream>

#include "granpack/core/error.h"

namespace granpack {

bool Range::contains(double x) const {
  if (std::isnan(x))
    return false;
  bool above = lo_open ? x > lo : x >= lo;
  bool below = hi_open ? x < hi : x <= hi;
  return above && below;
}

std::string Range::describe() const {
  std::ostringstream os;
  bool has_lo = std::isfinite(lo), has_hi = std::isfinite(hi);
  if (has_lo && has_hi)
    os << "in " << (lo_open ? "(" : "[") << lo << ", " << hi << (hi_open ? ")" : "]");
  else if (has_lo)
    os << (lo_open ? "> " : ">= ") << lo;
  else if (has_hi)
    os << (hi_open ? "< " : "<= ") << hi;
  else
    os << "any number";
  return os.str();
}

std::string toml_text(const toml::value& v) {
  std::ostringstream os;
  if (v.is_floating()) {
    // Shortest text that reads back to the same double: what the user typed, not 17 digits.
    char buf[64];
    double x = v.as_floating();
    if (std::isinf(x))
      return x > 0 ? "inf" : "-inf";
    if (std::isnan(x))
      return "nan";
    auto res = std::to_chars(buf, buf + sizeof buf, x);
    std::string s(buf, res.ptr);
    if (s.find_first_of(".e") == std::string::npos)
      s += ".0";
    return s;
  }
  if (v.is_array()) {
    std::string s = "[";
    for (const auto& e : v.as_array())
      s += (s.size() > 1 ? ", " : "") + toml_text(e);
    return s + "]";
  }
  if (v.is_string())
    os << '"' << v.as_string().str << '"';
  else if (v.is_table())
    os << "{table}";
  else
    os << toml::format(v, 0);
  std::string s = os.str();
  while (!s.empty() && (s.back() == '\n' || s.back() == ' '))
    s.pop_back();
  return s;
}

namespace {
/// The source text of a number's token ("" if the value has no source, e.g. built in code).
std::string token_of(const toml::value& v) {
  const auto loc = v.location();
  const std::string& line = loc.line_str();
  if (loc.column() < 1 || loc.column() - 1 >= line.size())
    return "";
  return line.substr(loc.column() - 1, loc.region());
}

/// "" if v holds what its token says; otherwise the problem, for a message.
std::string overflow_problem(const toml::value& v) {
  if (number_is_exact(v))
    return "";
  return "= " + token_of(v) + " does not fit in " +
         (v.is_integer() ? "a 64-bit integer" : "a double (largest about 1.8e308)");
}
} // namespace

bool number_is_exact(const toml::value& v) {
  if (!v.is_integer() && !v.is_floating())
    return true;
  std::string t = token_of(v);
  std::erase(t, '_');
  if (t.empty())
    return true;
  bool negative = false;
  if (t[0] == '+' || t[0] == '-') {
    negative = t[0] == '-';
    t.erase(0, 1);
  }
  if (v.is_floating()) {
    // toml11 reads floats with operator>>, which stores +-DBL_MAX on overflow: only that value
    // can be a clamped one, and it is genuine only if the token itself is in range.
    const double x = v.as_floating();
    if (!std::isfinite(x) || std::abs(x) != std::numeric_limits<double>::max())
      return true;
    double y = 0;
    const auto res = std::from_chars(t.data(), t.data() + t.size(), y);
    return res.ec == std::errc{};
  }
  int base = 10;
  if (t.size() > 2 && t[0] == '0' && (t[1] == 'x' || t[1] == 'o' || t[1] == 'b')) {
    base = t[1] == 'x' ? 16 : t[1] == 'o' ? 8 : 2;
    t.erase(0, 2);
  }
  std::uint64_t magnitude = 0;
  const auto res = std::from_chars(t.data(), t.data() + t.size(), magnitude, base);
  if (res.ec != std::errc{} || res.ptr != t.data() + t.size())
    return false;
  const std::uint64_t limit =
      negative ? std::uint64_t{1} << 63 : std::uint64_t(std::numeric_limits<std::int64_t>::max());
  if (magnitude > limit)
    return false;
  // Also compare with the stored value: toml11 sums binary digits in a signed integer, so a
  // 64-digit 0b literal wraps instead of clamping.
  const auto expect = static_cast<std::int64_t>(negative ? 0 - magnitude : magnitude);
  return expect == v.as_integer();
}

/// The value's TOML type with its article ("an integer"), for "= 1 is an integer, expected ...".
static const char* type_name(const toml::value& v) {
  switch (v.type()) {
  case toml::value_t::boolean:
    return "a boolean";
  case toml::value_t::integer:
    return "an integer";
  case toml::value_t::floating:
    return "a float";
  case toml::value_t::string:
    return "a string";
  case toml::value_t::array:
    return "an array";
  case toml::value_t::table:
    return "a table";
  default:
    return "a date/time";
  }
}

namespace {
/// Levenshtein distance, for "did you mean" hints on misspelt keys.
std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j)
    row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}
bool similar(const std::string& a, const std::string& b) {
  const std::size_t limit = std::max<std::size_t>(1, std::min(a.size(), b.size()) / 4);
  // The distance is at least the length difference: skip the quadratic computation for a
  // (possibly megabyte-long) key that cannot be a misspelling.
  const std::size_t diff = a.size() > b.size() ? a.size() - b.size() : b.size() - a.size();
  return diff <= limit && edit_distance(a, b) <= limit;
}
} // namespace

TableReader::TableReader(const toml::value& table, std::string file, std::string table_path)
    : table_(table), file_(std::move(file)), path_(std::move(table_path)) {}

std::string TableReader::where(const std::string& key) const {
  std::ostringstream os;
  os << file_;
  if (table_.is_table() && table_.as_table().count(key)) {
    auto line = table_.as_table().at(key).location().line();
    if (line > 0)
      os << ":" << line;
  }
  os << ": [" << path_ << "] " << key;
  return os.str();
}

void TableReader::fail(const std::string& key, const std::string& problem) const {
  throw InputError(where(key) + ": " + problem);
}

bool TableReader::has(const std::string& key) const {
  return table_.is_table() && table_.as_table().count(key) > 0;
}

const toml::value* TableReader::find(const std::string& key) {
  known_.insert(key);
  if (!has(key))
    return nullptr;
  return &table_.as_table().at(key);
}

void TableReader::fail_missing(const std::string& key, const std::string& what) const {
  // A required key is often missing because it is misspelt: report the misspelling instead.
  if (table_.is_table())
    for (const auto& [other, value] : table_.as_table())
      if (!known_.count(other) && similar(other, key))
        fail(other, "unknown key (did you mean '" + key + "'?)");
  fail(key, "missing required key (" + what + ")");
}

double TableReader::to_double(const std::string& key, const toml::value& v,
                              const std::string& what) {
  if (const std::string problem = overflow_problem(v); !problem.empty())
    fail(key, problem + " (" + what + ")");
  if (v.is_integer())
    return static_cast<double>(v.as_integer());
  if (v.is_floating())
    return v.as_floating();
  fail(key, "= " + toml_text(v) + " is " + type_name(v) + ", expected a number (" + what + ")");
}

double TableReader::number(const std::string& key, Range range, const std::string& what) {
  const toml::value* v = find(key);
  if (!v)
    fail_missing(key, what + ", " + range.describe());
  double x = to_double(key, *v, what);
  if (!range.contains(x))
    fail(key, "= " + toml_text(*v) + " is out of range: " + what + " must be " + range.describe());
  return x;
}

double TableReader::number_or(const std::string& key, double fallback, Range range,
                              const std::string& what) {
  if (!has(key)) {
    known_.insert(key);
    return fallback;
  }
  return number(key, range, what);
}

std::int64_t TableReader::integer(const std::string& key, Range range, const std::string& what) {
  const toml::value* v = find(key);
  if (!v)
    fail_missing(key, what + ", an integer " + range.describe());
  if (!v->is_integer())
    fail(key,
         "= " + toml_text(*v) + " is " + type_name(*v) + ", expected an integer (" + what + ")");
  if (const std::string problem = overflow_problem(*v); !problem.empty())
    fail(key, problem + " (" + what + ")");
  auto x = v->as_integer();
  if (!range.contains(static_cast<double>(x)))
    fail(key, "= " + toml_text(*v) + " is out of range: " + what + " must be " + range.describe());
  return x;
}

std::int64_t TableReader::integer_or(const std::string& key, std::int64_t fallback, Range range,
                                     const std::string& what) {
  if (!has(key)) {
    known_.insert(key);
    return fallback;
  }
  return integer(key, range, what);
}

std::string TableReader::choice(const std::string& key, const std::vector<std::string>& allowed,
                                const std::string& what) {
  std::string list;
  for (const auto& a : allowed)
    list += (list.empty() ? "\"" : ", \"") + a + "\"";
  const toml::value* v = find(key);
  if (!v)
    fail_missing(key, what + ", one of " + list);
  if (!v->is_string())
    fail(key,
         "= " + toml_text(*v) + " is " + type_name(*v) + ", expected a string, one of " + list);
  const std::string& s = v->as_string().str;
  for (const auto& a : allowed)
    if (s == a)
      return s;
  fail(key, "= " + toml_text(*v) + " is not allowed: " + what + " must be one of " + list);
}

std::string TableReader::choice_or(const std::string& key, const std::string& fallback,
                                   const std::vector<std::string>& allowed,
                                   const std::string& what) {
  if (!has(key)) {
    known_.insert(key);
    return fallback;
  }
  return choice(key, allowed, what);
}

std::string TableReader::string_or(const std::string& key, const std::string& fallback,
                                   const std::string& what) {
  const toml::value* v = find(key);
  if (!v)
    return fallback;
  if (!v->is_string())
    fail(key, "= " + toml_text(*v) + " is " + type_name(*v) + ", expected a string (" + what + ")");
  return v->as_string().str;
}

bool TableReader::boolean_or(const std::string& key, bool fallback, const std::string& what) {
  const toml::value* v = find(key);
  if (!v)
    return fallback;
  if (!v->is_boolean())
    fail(key,
         "= " + toml_text(*v) + " is " + type_name(*v) + ", expected true or false (" + what + ")");
  return v->as_boolean();
}

std::optional<std::vector<std::int64_t>> TableReader::integers_opt(const std::string& key,
                                                                   std::size_t count, Range range,
                                                                   const std::string& what) {
  const toml::value* v = find(key);
  if (!v)
    return std::nullopt;
  std::string expect = "expected an array of " + std::to_string(count) + " integers " +
                       range.describe() + " (" + what + ")";
  if (!v->is_array() || v->as_array().size() != count)
    fail(key, "= " + toml_text(*v) + ": " + expect);
  std::vector<std::int64_t> out;
  for (const auto& e : v->as_array()) {
    if (!e.is_integer() || !range.contains(static_cast<double>(e.as_integer())))
      fail(key, "= " + toml_text(*v) + ": " + expect);
    if (const std::string problem = overflow_problem(e); !problem.empty())
      fail(key, problem + " (" + what + ")");
    out.push_back(e.as_integer());
  }
  return out;
}

std::vector<std::int64_t> TableReader::integers(const std::string& key, std::size_t count,
                                                Range range, const std::string& what) {
  auto v = integers_opt(key, count, range, what);
  if (!v)
    fail_missing(key, what);
  return *v;
}

void TableReader::finish() const {
  if (!table_.is_table())
    return;
  for (const auto& [key, value] : table_.as_table()) {
    if (known_.count(key))
      continue;
    std::string list, hint;
    for (const auto& k : known_) {
      list += (list.empty() ? "" : ", ") + k;
      if (hint.empty() && similar(key, k))
        hint = " (did you mean '" + k + "'?)";
    }
    fail(key, "unknown key" + hint + "; allowed keys here: " + list);
  }
}

} // namespace granpack
