#include "granpack/io/deck.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>

#include "granpack/core/error.h"
#include "granpack/io/deck_reader.h"
#include "granpack/io/stage_table.h"

namespace granpack {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// A deck needs 2 levels of arrays/inline tables and no dotted keys; this is generous.
constexpr int kMaxNesting = 64;

/// toml11 3.7 sums the digits of a 0b literal in a signed 64-bit integer whose place value
/// overflows at the 63rd digit (undefined behaviour).
constexpr int kMaxBinaryDigits = 62;

/// Index of the first byte that does not belong to well-formed UTF-8 (no overlong forms, no
/// surrogates, nothing above U+10FFFF), or npos.
std::size_t invalid_utf8(const std::string& s) {
  std::size_t i = 0;
  while (i < s.size()) {
    const auto c = static_cast<unsigned char>(s[i]);
    const std::size_t len = c < 0x80                 ? 1
                            : c >= 0xC2 && c <= 0xDF ? 2
                            : c >= 0xE0 && c <= 0xEF ? 3
                            : c >= 0xF0 && c <= 0xF4 ? 4
                                                     : 0;
    if (len == 0 || i + len > s.size())
      return i;
    const unsigned lo = c == 0xE0 ? 0xA0 : c == 0xF0 ? 0x90 : 0x80;
    const unsigned hi = c == 0xED ? 0x9F : c == 0xF4 ? 0x8F : 0xBF;
    for (std::size_t k = 1; k < len; ++k) {
      const auto b = static_cast<unsigned char>(s[i + k]);
      if (b < (k == 1 ? lo : 0x80u) || b > (k == 1 ? hi : 0xBFu))
        return i;
    }
    i += len;
  }
  return std::string::npos;
}

/// Refuses, before parsing, what toml11 3.7 cannot take: text that is not UTF-8 (TOML
/// requires it, and toml11's error path for a bad byte inside a string reads out of bounds); nested
/// arrays and inline tables are parsed recursively (about 10^4 levels overflow the stack: a crash),
/// dotted keys in quadratic time (10^5 parts: minutes), long binary literals with undefined
/// behaviour. A light scan: strings and comments are skipped, brackets and braces counted, the dots
/// of a key path counted until the next '=', ',', bracket or line end, and 0b digits counted.
void check_toml11_limits(const std::string& text, const std::string& file) {
  int depth = 0, dots = 0;
  std::size_t line = 1, i = 0;
  const std::size_t n = text.size();
  auto fail = [&] {
    throw InputError(file + ":" + std::to_string(line) +
                     ": arrays, inline tables or dotted keys nested more than " +
                     std::to_string(kMaxNesting) + " levels deep (see docs/deck.md)");
  };
  if (const std::size_t bad = invalid_utf8(text); bad != std::string::npos) {
    char byte[8];
    std::snprintf(byte, sizeof byte, "0x%02X", static_cast<unsigned char>(text[bad]));
    throw InputError(file + ":" +
                     std::to_string(1 + std::count(text.begin(), text.begin() + bad, '\n')) +
                     ": invalid UTF-8 (byte " + byte + "): a deck must be UTF-8 text");
  }
  auto binary_digits = [&](std::size_t at) { // at: just after "0b"
    int digits = 0;
    for (; at < n && (text[at] == '0' || text[at] == '1' || text[at] == '_'); ++at)
      digits += text[at] != '_';
    return digits;
  };
  while (i < n) {
    const char c = text[i];
    if (c == '\n') {
      ++line, ++i, dots = 0;
    } else if (c == '#') {
      while (i < n && text[i] != '\n')
        ++i;
    } else if (c == '"' || c == '\'') {
      const bool multi = text.compare(i, 3, std::string(3, c)) == 0;
      const std::size_t quote = multi ? 3 : 1;
      i += quote;
      while (i < n) {
        if (text[i] == '\n') {
          if (!multi)
            break; // unterminated: the parser reports it (the line is counted outside)
          ++line;
        }
        if (c == '"' && text[i] == '\\' && i + 1 < n) {
          if (text[i + 1] == '\n') {
            if (!multi)
              break;
            ++line;
          }
          i += 2;
          continue;
        }
        if (text.compare(i, quote, std::string(quote, c)) == 0) {
          i += quote;
          break;
        }
        ++i;
      }
    } else {
      if (c == '[' || c == '{') {
        if (++depth > kMaxNesting)
          fail();
        dots = 0;
      } else if (c == ']' || c == '}') {
        depth = std::max(depth - 1, 0);
        dots = 0;
      } else if (c == '=' || c == ',') {
        dots = 0;
      } else if (c == '.' && ++dots > kMaxNesting) {
        fail();
      } else if (c == '0' && i + 1 < n && text[i + 1] == 'b' &&
                 binary_digits(i + 2) > kMaxBinaryDigits) {
        throw InputError(
            file + ":" + std::to_string(line) + ": a binary integer (0b...) of more than " +
            std::to_string(kMaxBinaryDigits) + " digits does not fit in a 64-bit integer");
      }
      ++i;
    }
  }
}

const toml::value& sub_table(const toml::value& root, const std::string& file,
                             const std::string& name, bool required) {
  static const toml::value empty = toml::table{};
  if (!root.as_table().count(name)) {
    if (!required)
      return empty;
    TableReader top(root, file, "top level");
    top.fail_missing(name, "table [" + name + "], see docs/deck.md");
  }
  const toml::value& t = root.as_table().at(name);
  if (!t.is_table())
    throw InputError(file + ":" + std::to_string(t.location().line()) + ": '" + name +
                     "' must be a table [" + name + "], found " + toml_text(t));
  return t;
}

SampleSpec read_sample(TableReader& r) {
  SampleSpec s;
  s.dimension =
      static_cast<int>(r.integer("dimension", Range::closed(2, 3), "space dimension, 2 or 3"));
  s.n = r.integer("n", {1, 1e12}, "number of grains");
  s.diameter = r.number("diameter", Range::positive(), "grain diameter a in m");
  s.distribution = r.choice_or("distribution", "monodisperse", {"monodisperse", "uniform"},
                               "diameter distribution");
  s.min_diameter_ratio = r.number_or("min_diameter_ratio", 0.5, Range{0.0, 1.0, true, false},
                                     "smallest/largest diameter for distribution = \"uniform\"");
  if (s.distribution == "monodisperse" && r.has("min_diameter_ratio"))
    r.fail("min_diameter_ratio", "only applies to distribution = \"uniform\"");
  s.seed =
      static_cast<std::uint64_t>(r.integer_or("seed", 1, Range::non_negative(), "random seed"));
  r.finish();
  return s;
}

MaterialSpec read_material(TableReader& r) {
  MaterialSpec m;
  m.density = r.number("density", Range::positive(), "grain density in kg/m^3");
  m.normal_law = r.choice_or("normal_law", "hertz", {"hertz", "linear"}, "normal elasticity");
  if (m.normal_law == "hertz") {
    m.young_modulus = r.number("young_modulus", Range::positive(), "Young modulus E in Pa");
    m.poisson_ratio = r.number("poisson_ratio", Range::half_open(-1.0, 0.5), "Poisson ratio nu");
    m.walton_rescaling = r.boolean_or("walton_rescaling", true,
                                      "scale T down by K_T(N_new)/K_T(N_old) when N^e decreases");
    if (r.has("normal_stiffness") || r.has("tangential_stiffness_ratio"))
      r.fail(r.has("normal_stiffness") ? "normal_stiffness" : "tangential_stiffness_ratio",
             "only applies to normal_law = \"linear\" (Hertz stiffnesses follow from E and nu)");
  } else {
    m.normal_stiffness = r.number("normal_stiffness", Range::positive(), "K_N in N/m");
    m.tangential_stiffness_ratio =
        r.number_or("tangential_stiffness_ratio", 1.0, Range::non_negative(), "K_T/K_N");
    for (const char* key : {"young_modulus", "poisson_ratio", "walton_rescaling"})
      if (r.has(key))
        r.fail(key, "only applies to normal_law = \"hertz\"");
  }
  m.friction = r.number("friction", Range::non_negative(), "friction coefficient mu (inf allowed)");
  m.damping =
      r.number("damping", Range::half_open(0.0, 1.0), "viscous damping zeta, fraction of critical");
  m.damping_tension = r.boolean_or("damping_tension", true,
                                   "may the viscous force make a contact pull (N^e + N^v < 0)");
  // [GRC] cohesion and rolling resistance: optional, both keys of a pair or neither.
  const Range finite = Range::half_open(0.0, std::numeric_limits<double>::infinity());
  m.cohesion_force = r.number_or("cohesion_force", 0.0, finite, "maximum attractive force F0 in N");
  m.cohesion_range = r.number_or("cohesion_range", 0.0, finite, "range D0 of the attraction in m");
  if ((m.cohesion_force > 0) != (m.cohesion_range > 0))
    r.fail(m.cohesion_force > 0 ? "cohesion_range" : "cohesion_force",
           "cohesion needs both cohesion_force (F0 > 0, N) and cohesion_range (D0 > 0, m)");
  m.rolling_stiffness =
      r.number_or("rolling_stiffness", 0.0, finite, "rolling stiffness K_r in N m per radian");
  m.rolling_friction = r.number_or("rolling_friction", 0.0, Range::non_negative(),
                                   "rolling friction mu_r in m (inf allowed)");
  m.rolling_damping = r.number_or("rolling_damping", 0.0, Range::half_open(0.0, 1.0),
                                  "rolling damping zeta_r, fraction of critical (not in [GRC])");
  if ((m.rolling_friction > 0 || m.rolling_damping > 0) && !(m.rolling_stiffness > 0))
    r.fail("rolling_stiffness",
           std::string(m.rolling_friction > 0 ? "rolling_friction" : "rolling_damping") +
               " > 0 needs a rolling_stiffness K_r > 0");
  r.finish();
  return m;
}

NumericsSpec read_numerics(TableReader& r) {
  NumericsSpec n;
  n.time_step_fraction =
      r.number_or("time_step_fraction", n.time_step_fraction, Range{0.0, 0.2, true, false},
                  "time step / contact duration of the stiffest contact");
  n.skin = r.number_or("skin", n.skin, Range{0.0, 1.0, true, false},
                       "Verlet skin as a fraction of the diameter");
  n.max_overlap =
      r.number_or("max_overlap", n.max_overlap, Range{0.0, 1.0, true, false},
                  "largest overlap / smaller radius before a run stops (a blow-up check)");
  n.load_balance = r.boolean_or("load_balance", n.load_balance,
                                "move the domain cut planes to balance the grain counts");
  n.load_balance_threshold =
      r.number_or("load_balance_threshold", n.load_balance_threshold,
                  Range{1.0, std::numeric_limits<double>::infinity(), true, false},
                  "largest rank's grain count over the mean above which the cut planes move");
  n.halo = r.choice_or("halo", n.halo, {"messages", "shared_memory"}, "the halo's transport");
  r.finish();
  return n;
}

OutputSpec read_output(TableReader& r) {
  OutputSpec o;
  o.log_every = r.integer_or("log_every", o.log_every, {1, 1e15}, "steps between progress lines");
  o.quiet = r.boolean_or("quiet", o.quiet, "suppress progress lines");
  o.checkpoint_every_steps = r.integer_or("checkpoint_every_steps", 0, Range::non_negative(),
                                          "steps between checkpoints (0: off)");
  o.checkpoint_every_seconds =
      r.number_or("checkpoint_every_seconds", 3600.0, Range::non_negative(),
                  "wall seconds between checkpoints (0: off)");
  o.trajectory_every = r.integer_or("trajectory_every", 0, Range::non_negative(),
                                    "steps between trajectory snapshots (0: off)");
  o.trajectory_every_time = r.number_or(
      "trajectory_every_time", 0.0, Range::half_open(0.0, std::numeric_limits<double>::infinity()),
      "simulated seconds between trajectory snapshots (0: off; finite)");
  o.trajectory_stage_ends = r.boolean_or("trajectory_stage_ends", false,
                                         "a trajectory snapshot at the end of every stage");
  r.finish();
  return o;
}

StageSpec read_stage(const toml::value& v, int index, const std::string& file,
                     const SampleSpec& sample, const MaterialSpec& material, bool after_compress) {
  std::string path = "stage[" + std::to_string(index) + "]";
  if (!v.is_table())
    throw InputError(file + ": " + path + " must be a table ([[stage]])");
  TableReader r(v, file, path);
  StageSpec st;
  st.index = index;
  st.kind = r.choice("kind", stage_kinds(), "stage kind");
  st.name = r.string_or("name", st.kind, "label of the stage in logs and report.json");
  TableReader rk(v, file, path + " (" + st.kind + ")");
  rk.accept("kind");
  rk.accept("name");
  StageTable table{rk, v, sample, material, index, after_compress};
  st.params = parse_stage_params(st.kind, table);
  rk.finish();
  return st;
}

} // namespace

Deck parse_deck(const std::string& text, const std::string& file_name) {
  Deck deck;
  deck.file = file_name;
  deck.text = text;
  toml::value root;
  check_toml11_limits(text, file_name);
  try {
    std::istringstream is(text);
    root = toml::parse(is, file_name);
  } catch (const toml::syntax_error& e) {
    throw InputError(file_name + ": TOML syntax error at line " +
                     std::to_string(e.location().line()) + ":\n" + e.what());
  }
  const toml::value& sample = sub_table(root, file_name, "sample", true);
  const toml::value& material = sub_table(root, file_name, "material", true);
  const toml::value& numerics = sub_table(root, file_name, "numerics", false);
  const toml::value& output = sub_table(root, file_name, "output", false);
  TableReader top(root, file_name, "top level");
  for (const char* t : {"sample", "material", "numerics", "output", "stage"})
    top.accept(t);
  top.finish();

  TableReader rs(sample, file_name, "sample");
  deck.sample = read_sample(rs);
  TableReader rm(material, file_name, "material");
  deck.material = read_material(rm);
  TableReader rn(numerics, file_name, "numerics");
  deck.numerics = read_numerics(rn);
  TableReader ro(output, file_name, "output");
  deck.output = read_output(ro);

  if (!root.as_table().count("stage"))
    throw InputError(file_name +
                     ": no stages: add at least one [[stage]] table (see docs/deck.md)");
  const toml::value& stages = root.as_table().at("stage");
  if (!stages.is_array())
    throw InputError(file_name + ":" + std::to_string(stages.location().line()) +
                     ": 'stage' must be an array of tables, written [[stage]]");
  int index = 0;
  bool after_compress = false;
  for (const auto& s : stages.as_array()) {
    deck.stages.push_back(
        read_stage(s, index++, file_name, deck.sample, deck.material, after_compress));
    after_compress = after_compress || deck.stages.back().kind == "compress";
  }
  if (deck.stages.empty())
    throw InputError(file_name + ": no stages: add at least one [[stage]] table");
  return deck;
}

std::string read_deck_text(const std::filesystem::path& path) {
  if (std::filesystem::is_directory(path))
    throw InputError(path.string() + ": is a directory, not a deck file");
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw InputError(path.string() + ": cannot open the deck file (does it exist?)");
  std::ostringstream os;
  os << in.rdbuf();
  if (in.bad())
    throw InputError(path.string() + ": read error");
  return os.str();
}

Deck load_deck(const std::filesystem::path& path) {
  return parse_deck(read_deck_text(path), path.string());
}

} // namespace granpack
