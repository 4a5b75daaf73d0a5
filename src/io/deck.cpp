#include "granpack/io/deck.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <numbers>
#include <sstream>

#include "granpack/core/error.h"
#include "granpack/io/deck_reader.h"

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
    const std::size_t len = c < 0x80                ? 1
                            : c >= 0xC2 && c <= 0xDF ? 2
                            : c >= 0xE0 && c <= 0xEF ? 3
                            : c >= 0xF0 && c <= 0xF4 ? 4
                                                     : 0;
    if (len == 0 || i + len > s.size()) return i;
    const unsigned lo = c == 0xE0 ? 0xA0 : c == 0xF0 ? 0x90 : 0x80;
    const unsigned hi = c == 0xED ? 0x9F : c == 0xF4 ? 0x8F : 0xBF;
    for (std::size_t k = 1; k < len; ++k) {
      const auto b = static_cast<unsigned char>(s[i + k]);
      if (b < (k == 1 ? lo : 0x80u) || b > (k == 1 ? hi : 0xBFu)) return i;
    }
    i += len;
  }
  return std::string::npos;
}

/// Refuses, before parsing, what toml11 3.7 cannot take: text that is not UTF-8 (TOML
/// requires it, and toml11's error path for a bad byte inside a string reads out of bounds); nested arrays and inline tables are
/// parsed recursively (about 10^4 levels overflow the stack: a crash), dotted keys in
/// quadratic time (10^5 parts: minutes), long binary literals with undefined behaviour. A
/// light scan: strings and comments are skipped, brackets and braces counted, the dots of a
/// key path counted until the next '=', ',', bracket or line end, and 0b digits counted.
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
  auto binary_digits = [&](std::size_t at) {  // at: just after "0b"
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
      while (i < n && text[i] != '\n') ++i;
    } else if (c == '"' || c == '\'') {
      const bool multi = text.compare(i, 3, std::string(3, c)) == 0;
      const std::size_t quote = multi ? 3 : 1;
      i += quote;
      while (i < n) {
        if (text[i] == '\n') {
          if (!multi) break;  // unterminated: the parser reports it (the line is counted outside)
          ++line;
        }
        if (c == '"' && text[i] == '\\' && i + 1 < n) {
          if (text[i + 1] == '\n') {
            if (!multi) break;
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
        if (++depth > kMaxNesting) fail();
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
        throw InputError(file + ":" + std::to_string(line) + ": a binary integer (0b...) of more than " +
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
    if (!required) return empty;
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
  s.dimension = static_cast<int>(r.integer("dimension", Range::closed(2, 3), "space dimension, 2 or 3"));
  s.n = r.integer("n", {1, 1e12}, "number of grains");
  s.diameter = r.number("diameter", Range::positive(), "grain diameter a in m");
  s.distribution = r.choice_or("distribution", "monodisperse", {"monodisperse", "uniform"},
                               "diameter distribution");
  s.min_diameter_ratio = r.number_or("min_diameter_ratio", 0.5, Range{0.0, 1.0, true, false},
                                     "smallest/largest diameter for distribution = \"uniform\"");
  if (s.distribution == "monodisperse" && r.has("min_diameter_ratio"))
    r.fail("min_diameter_ratio", "only applies to distribution = \"uniform\"");
  s.seed = static_cast<std::uint64_t>(r.integer_or("seed", 1, Range::non_negative(), "random seed"));
  r.finish();
  return s;
}

MaterialSpec read_material(TableReader& r) {
  MaterialSpec m;
  m.density = r.number("density", Range::positive(), "grain density in kg/m^3");
  m.normal_law = r.choice_or("normal_law", "hertz", {"hertz", "linear"}, "normal elasticity");
  if (m.normal_law == "hertz") {
    m.young_modulus = r.number("young_modulus", Range::positive(), "Young modulus E in Pa");
    m.poisson_ratio = r.number("poisson_ratio", Range::half_open(-1.0, 0.5),
                               "Poisson ratio nu");
    if (r.has("normal_stiffness") || r.has("tangential_stiffness_ratio"))
      r.fail(r.has("normal_stiffness") ? "normal_stiffness" : "tangential_stiffness_ratio",
             "only applies to normal_law = \"linear\" (Hertz stiffnesses follow from E and nu)");
  } else {
    m.normal_stiffness = r.number("normal_stiffness", Range::positive(), "K_N in N/m");
    m.tangential_stiffness_ratio = r.number_or("tangential_stiffness_ratio", 1.0,
                                               Range::non_negative(), "K_T/K_N");
    if (r.has("young_modulus") || r.has("poisson_ratio"))
      r.fail(r.has("young_modulus") ? "young_modulus" : "poisson_ratio",
             "only applies to normal_law = \"hertz\"");
  }
  m.friction = r.number("friction", Range::non_negative(), "friction coefficient mu (inf allowed)");
  m.damping = r.number("damping", Range::half_open(0.0, 1.0),
                       "viscous damping zeta, fraction of critical");
  // [GRC] cohesion and rolling resistance: optional, both keys of a pair or neither.
  const Range finite = Range::half_open(0.0, std::numeric_limits<double>::infinity());
  m.cohesion_force = r.number_or("cohesion_force", 0.0, finite,
                                 "maximum attractive force F0 in N");
  m.cohesion_range = r.number_or("cohesion_range", 0.0, finite,
                                 "range D0 of the attraction in m");
  if ((m.cohesion_force > 0) != (m.cohesion_range > 0))
    r.fail(m.cohesion_force > 0 ? "cohesion_range" : "cohesion_force",
           "cohesion needs both cohesion_force (F0 > 0, N) and cohesion_range (D0 > 0, m)");
  m.rolling_stiffness = r.number_or("rolling_stiffness", 0.0, finite,
                                    "rolling stiffness K_r in N m per radian");
  m.rolling_friction = r.number_or("rolling_friction", 0.0, Range::non_negative(),
                                   "rolling friction mu_r in m (inf allowed)");
  m.rolling_damping = r.number_or("rolling_damping", 0.0, Range::half_open(0.0, 1.0),
                                  "rolling damping zeta_r, fraction of critical (not in [GRC])");
  if ((m.rolling_friction > 0 || m.rolling_damping > 0) && !(m.rolling_stiffness > 0))
    r.fail("rolling_stiffness", std::string(m.rolling_friction > 0 ? "rolling_friction" : "rolling_damping") +
                                    " > 0 needs a rolling_stiffness K_r > 0");
  r.finish();
  return m;
}

NumericsSpec read_numerics(TableReader& r) {
  NumericsSpec n;
  n.time_step_fraction = r.number_or("time_step_fraction", n.time_step_fraction,
                                     Range{0.0, 0.2, true, false},
                                     "time step / contact duration of the stiffest contact");
  n.skin = r.number_or("skin", n.skin, Range{0.0, 1.0, true, false},
                       "Verlet skin as a fraction of the diameter");
  n.max_overlap = r.number_or("max_overlap", n.max_overlap, Range{0.0, 1.0, true, false},
                              "largest overlap / smaller radius before a run stops (a blow-up check)");
  r.finish();
  return n;
}

OutputSpec read_output(TableReader& r) {
  OutputSpec o;
  o.log_every = r.integer_or("log_every", o.log_every, {1, 1e15}, "steps between progress lines");
  o.quiet = r.boolean_or("quiet", o.quiet, "suppress progress lines");
  o.checkpoint_every_steps = r.integer_or("checkpoint_every_steps", 0, Range::non_negative(),
                                          "steps between checkpoints (0: off)");
  o.checkpoint_every_seconds = r.number_or("checkpoint_every_seconds", 3600.0,
                                           Range::non_negative(),
                                           "wall seconds between checkpoints (0: off)");
  r.finish();
  return o;
}

LatticeStage read_lattice(TableReader& r, const SampleSpec& sample) {
  LatticeStage s;
  std::string fallback = sample.dimension == 3 ? "fcc" : "hex";
  s.lattice = r.choice_or("lattice", fallback, {sample.dimension == 3 ? "fcc" : "hex"},
                          sample.dimension == 3 ? "lattice in 3D" : "lattice in 2D");
  double phi_max = sample.dimension == 3 ? std::numbers::pi / std::sqrt(18.0) : std::numbers::pi / std::sqrt(12.0);
  s.phi = r.number("phi", Range{0.0, phi_max, true, false},
                   "solid fraction (at most the close-packed value)");
  if (sample.distribution != "monodisperse")
    r.fail("lattice", "a lattice needs [sample] distribution = \"monodisperse\"");
  const std::int64_t per_cell = sample.dimension == 3 ? 4 : 2;
  auto cells = r.integers_opt("cells", sample.dimension, {1, 1e6}, "unit cells per axis");
  if (cells) {
    std::int64_t prod = per_cell;
    for (auto c : *cells) prod *= c;
    if (prod != sample.n)
      r.fail("cells", "= " + toml_text(toml::value(*cells)) + " holds " + std::to_string(prod) +
                          " grains but [sample] n = " + std::to_string(sample.n));
    s.cells = *cells;
  } else {
    // Cubic (3D) or near-square (2D) default when n allows it.
    auto k = static_cast<std::int64_t>(
        std::llround(std::pow(double(sample.n) / per_cell, 1.0 / sample.dimension)));
    std::int64_t prod = per_cell;
    for (int a = 0; a < sample.dimension; ++a) prod *= k;
    if (prod != sample.n)
      r.fail("cells", "missing: [sample] n = " + std::to_string(sample.n) + " is not " +
                          std::to_string(per_cell) + " k^" + std::to_string(sample.dimension) +
                          "; give cells = [..] with " + std::to_string(per_cell) +
                          " x product = n");
    s.cells.assign(sample.dimension, k);
  }
  return s;
}

EquilibriumTolerances read_tolerances(TableReader& r) {
  EquilibriumTolerances t;
  t.force = r.number_or("tolerance_force", t.force, Range::positive(),
                        "max net force per grain / F1 (F1 = max(F0, a^2 P))");
  t.stress = r.number_or("tolerance_stress", t.stress, Range::positive(),
                         "max |sigma_aa - P| / (F1 / a^2)");
  t.kinetic = r.number_or("tolerance_kinetic", t.kinetic, Range::positive(),
                          "kinetic energy per grain / (F1 a)");
  t.moment = r.number_or("tolerance_moment", t.moment, Range::positive(),
                         "max net moment per grain / (F1 a) (inf: not checked)");
  return t;
}

/// The raw value of a key of a table known to hold it.
const toml::value& v_table(const toml::value& table, const std::string& key) {
  return table.as_table().at(key);
}

/// The keys of the stress-controlled cell (compress, pressure_steps, stiffen).
void read_cell_controls(TableReader& rk, CompressStage& c) {
  if (rk.has("inertia_max"))
    c.inertia_max = rk.number("inertia_max", Range::positive(),
                              "cap on the inertia number I of the strain rate");
  if (rk.has("strain_rate_max"))
    c.strain_rate_max = rk.number("strain_rate_max", Range::positive(),
                                  "cap on the strain rate |dL/dt| / L in 1/s");
  c.cell_mass = rk.number_or("cell_mass", 1.0, Range::positive(),
                             "generalised cell mass M / total grain mass");
  c.cell_mass_per_length = rk.boolean_or("cell_mass_per_length", false,
                                         "M = cell_mass x total grain mass x a / L0 ([GRC] eq. 3)");
}

/// The keys compress and pressure_steps share.
void read_compress_controls(TableReader& rk, CompressStage& c) {
  read_cell_controls(rk, c);
  c.max_steps = rk.integer_or("max_steps", 0, Range::non_negative(), "step limit (0: none)");
  c.quench_interval = rk.integer_or("quench_interval", 0, Range::non_negative(),
                                    "steps between velocity quenches of a static packing (0: never)");
  c.quench_always = rk.choice_or("quench_when", "static", {"static", "always"},
                                 "which states are quenched: static ones (force and stress criteria "
                                 "hold) or all, the cell's rate too") == "always";
  c.tolerance = read_tolerances(rk);
}

/// The prescribed stress of a stress-controlled stage: `fixed_axes`, then `stress` (per
/// axis) or `pressure`; zero is allowed only with cohesion ([GRC]'s P* = 0).
void read_stress_target(TableReader& rk, const toml::value& v, const SampleSpec& sample,
                      bool cohesive, CompressStage& c) {
  const int dim = sample.dimension;
  const char* axis_names[] = {"x", "y", "z"};
  c.fixed.assign(dim, false);
  if (rk.has("fixed_axes")) {
    const toml::value& arr = v_table(v, "fixed_axes");
    bool ok = arr.is_array();
    if (ok)
      for (const auto& e : arr.as_array()) {
        int axis = -1;
        for (int a = 0; a < dim; ++a)
          if (e.is_string() && e.as_string().str == axis_names[a]) axis = a;
        if (axis < 0 || c.fixed[axis]) ok = false;
        else c.fixed[axis] = true;
      }
    rk.accept("fixed_axes");
    if (!ok)
      rk.fail("fixed_axes", "= " + toml_text(arr) + ": expected an array of distinct axis names among " +
                                std::string(dim == 3 ? "\"x\", \"y\", \"z\"" : "\"x\", \"y\""));
    int n_fixed = 0;
    for (bool f : c.fixed) n_fixed += f;
    if (n_fixed == dim) rk.fail("fixed_axes", "fixes every axis: nothing is stress-controlled");
  }
  if (rk.has("stress")) {
    if (rk.has("pressure")) rk.fail("stress", "give either pressure (isotropic) or stress (per axis), not both");
    const toml::value& arr = v_table(v, "stress");
    rk.accept("stress");
    bool ok = arr.is_array() && arr.as_array().size() == std::size_t(dim);
    if (ok)
      for (const auto& e : arr.as_array()) {
        double x = e.is_floating() ? e.as_floating() : e.is_integer() ? double(e.as_integer()) : -1;
        ok = ok && (cohesive ? x >= 0 : x > 0) && std::isfinite(x) && number_is_exact(e);
        c.stress.push_back(x);
      }
    if (!ok)
      rk.fail("stress", "= " + toml_text(arr) + ": expected " + std::to_string(dim) +
                            std::string(cohesive ? " non-negative" : " positive") +
                            " prescribed stresses Sigma_a in Pa, one per axis (zero needs cohesion)");
  } else {
    c.pressure = rk.number("pressure", cohesive ? Range::non_negative() : Range::positive(),
                           cohesive ? "prescribed pressure P in Pa ([GRC] P* = 0 allowed)"
                                    : "prescribed pressure P in Pa (P = 0 needs cohesion)");
    c.stress.assign(dim, c.pressure);
  }
  double sum = 0;
  int controlled = 0;
  for (int a = 0; a < dim; ++a)
    if (!c.fixed[a]) sum += c.stress[a], ++controlled;
  c.pressure = sum / controlled;
}

std::uint64_t read_seed(TableReader& rk, const SampleSpec& sample, int index) {
  // The default is computed unsigned: [sample] seed may be as large as INT64_MAX, and the
  // signed sum overflowed (undefined behaviour; in practice a negative seed).
  if (!rk.has("seed"))
    return sample.seed + 1000 + static_cast<std::uint64_t>(index);
  return static_cast<std::uint64_t>(
      rk.integer("seed", Range::non_negative(), "random seed of the stage"));
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
  if (st.kind == "lattice") {
    st.params = read_lattice(rk, sample);
  } else if (st.kind == "random") {
    // Overlap removal (prep/overlap_removal) stays far from jamming below these values.
    double phi_max = sample.dimension == 3 ? 0.55 : 0.70;
    RandomStage rs{rk.number("phi", Range{0.0, phi_max, true, false},
                            "solid fraction of the random placement")};
    rs.placement = rk.choice_or("placement", "relax", {"relax", "sequential"},
                               "the placement (relax: overlaps removed, pairs left "
                               "touching; sequential: random sequential addition)");
    st.params = rs;
  } else if (st.kind == "compress") {
    CompressStage c;
    read_stress_target(rk, v, sample, material.cohesion_force > 0, c);
    read_compress_controls(rk, c);
    if (c.inertia_max && !(c.pressure > 0))
      rk.fail("inertia_max", "needs P > 0 (I = eps_dot sqrt(m / (a P))); at P = 0 cap the rate with strain_rate_max");
    st.params = c;
  } else if (st.kind == "set") {
    SetStage s;
    if (rk.has("friction"))
      s.friction = rk.number("friction", Range::non_negative(), "new friction coefficient");
    if (rk.has("damping"))
      s.damping = rk.number("damping", Range::half_open(0.0, 1.0), "new damping fraction zeta");
    if (!s.friction && !s.damping)
      rk.fail("kind", "= \"set\" changes nothing: give friction and/or damping");
    st.params = s;
  } else if (st.kind == "write") {
    std::string f = rk.string_or("file", "", "HDF5 file name relative to the output directory");
    if (f.empty()) rk.fail("file", "missing required key (HDF5 file name, e.g. \"after_compress.h5\")");
    if (f.find('/') != std::string::npos || f.size() < 4 || f.substr(f.size() - 3) != ".h5")
      rk.fail("file", "= \"" + f + "\": must be a plain file name ending in .h5 (no directories)");
    st.params = WriteStage{f};
  } else if (st.kind == "read") {
    if (index != 0) rk.fail("kind", "= \"read\" must be the first stage (it builds the sample)");
    std::string f = rk.string_or("file", "", "configuration file (.h5) written by granpack");
    if (f.empty()) rk.fail("file", "missing required key (a granpack .h5 file, e.g. \"out/A/A.h5\")");
    // "{seed}" is the sample's seed: each sample of an ensemble reads its own file, e.g. the
    // A.h5 of the same sample of another ensemble (docs/deck.md, "read").
    for (std::size_t at = f.find("{seed}"); at != std::string::npos; at = f.find("{seed}", at))
      f.replace(at, 6, std::to_string(sample.seed));
    st.params = ReadStage{f};
  } else if (st.kind == "ed_gas") {
    EdGasStage e;
    e.collisions_per_grain = rk.number("collisions_per_grain", Range::positive(),
                                       "mean number of collisions per grain (n_coll)");
    e.seed = read_seed(rk, sample, index);
    st.params = e;
  } else if (st.kind == "ls_compress") {
    LsCompressStage l;
    const double phi_max = sample.dimension == 3 ? 0.64 : 0.82;
    l.phi = rk.number("phi", Range::open(0.0, phi_max), "target solid fraction (below jamming)");
    l.growth_rate = rk.number_or("growth_rate", l.growth_rate, Range::positive(),
                                 "d(diameter)/dt in units of the rms velocity");
    l.rescale_every = rk.number_or("rescale_every", l.rescale_every, Range::positive(),
                                   "collisions per grain between kinetic-energy resets");
    if (rk.has("report_phi")) {
      const toml::value& arr = v_table(v, "report_phi");
      rk.accept("report_phi");
      l.report_phi.clear();
      bool ok = arr.is_array();
      if (ok)
        for (const auto& e : arr.as_array()) {
          const double x = e.is_floating() ? e.as_floating() : e.is_integer() ? double(e.as_integer()) : -1;
          ok = ok && x > 0 && x < l.phi && (l.report_phi.empty() || x > l.report_phi.back());
          l.report_phi.push_back(x);
        }
      if (!ok)
        rk.fail("report_phi", "= " + toml_text(arr) + ": expected increasing solid fractions below phi");
    } else {
      std::erase_if(l.report_phi, [&](double x) { return x >= l.phi; });
    }
    l.seed = read_seed(rk, sample, index);
    st.params = l;
  } else if (st.kind == "expand") {
    st.params = ExpandStage{rk.number("factor", Range{1.0, 2.0, true, false},
                                      "homothetic expansion factor lambda, in (1, 2]")};
  } else if (st.kind == "pressure_steps") {
    if (!after_compress)
      rk.fail("kind", "= \"pressure_steps\" needs an earlier compress stage: its pressure is P_0");
    PressureStepsStage ps;
    ps.factor = rk.number("factor", Range::positive(), "pressure ratio between levels (e.g. 3.1623)");
    if (ps.factor == 1.0) rk.fail("factor", "= 1: the pressure would not change");
    ps.count = rk.integer("count", {1, 1000}, "number of pressure levels");
    ps.write = rk.boolean_or("write", true, "write each equilibrated level to <name>_<k>.h5");
    read_compress_controls(rk, ps.compress);
    st.params = ps;
  } else if (st.kind == "fix_rattlers") {
    FixRattlersStage f;
    if (rk.has("pressure"))
      f.pressure = rk.number("pressure", Range::positive(), "pressure P of the packing (Pa), the push scale");
    else if (!after_compress)
      rk.fail("kind", "= \"fix_rattlers\" needs an earlier compress stage (an equilibrated backbone) "
                      "or a `pressure` key (after a read stage)");
    f.force = rk.number_or("force", f.force, Range::open(0.0, 1.0), "push magnitude / (a^2 P)");
    f.tolerance = rk.number_or("tolerance", f.tolerance, Range::open(0.0, 1.0),
                               "net force on every rattler / push magnitude at equilibrium");
    f.max_steps = rk.integer_or("max_steps", 0, Range::non_negative(), "step limit (0: none)");
    f.seed = read_seed(rk, sample, index);
    st.params = f;
  } else if (st.kind == "aggregate") {
    AggregateStage g;
    g.velocity_ratio = rk.number("velocity_ratio", Range::positive(),
                                 "V0/V*: rms velocity of the Maxwell distribution over V* = "
                                 "sqrt(F0 D0 / m) ([GRC]: 9.48)");
    g.max_steps = rk.integer_or("max_steps", 0, Range::non_negative(), "step limit (0: none)");
    g.cluster_every = rk.integer_or("cluster_every", g.cluster_every, Range::positive(),
                                    "steps between cluster counts");
    g.quench_interval = rk.integer_or("quench_interval", 0, Range::non_negative(),
                                      "steps between velocity quenches once there is one cluster (0: never)");
    g.quench_delay = rk.integer_or("quench_delay", 0, Range::non_negative(),
                                   "steps from the first single cluster to the first quench");
    g.tolerance = read_tolerances(rk);
    g.seed = read_seed(rk, sample, index);
    st.params = g;
  } else if (st.kind == "stiffen") {
    if (material.normal_law != "linear")
      rk.fail("kind", "= \"stiffen\" ramps the linear law's K_N: needs [material] normal_law = \"linear\"");
    StiffenStage f;
    f.normal_stiffness = rk.number("normal_stiffness", Range::positive(), "target normal stiffness K_N in N/m");
    f.steps = rk.integer("steps", Range::positive(), "time steps of the ramp");
    f.increments = rk.integer_or("increments", f.increments, Range::closed(1.0, double(f.steps)),
                                 "equal geometric factors of the ramp (at most steps)");
    f.scale_rolling = rk.boolean_or("scale_rolling_stiffness", true,
                                    "the rolling stiffness K_r follows K_N");
    read_stress_target(rk, v, sample, material.cohesion_force > 0, f.control);
    read_cell_controls(rk, f.control);
    if (f.control.inertia_max && !(f.control.pressure > 0))
      rk.fail("inertia_max", "needs P > 0 (I = eps_dot sqrt(m / (a P))); at P = 0 cap the rate with strain_rate_max");
    st.params = f;
  }
  rk.finish();
  return st;
}

}  // namespace

const std::vector<std::string>& stage_kinds() {
  static const std::vector<std::string> kinds = {
      "lattice", "random", "read", "ed_gas",       "ls_compress", "expand",
      "compress", "pressure_steps", "fix_rattlers", "set",         "write",
      "aggregate", "stiffen"};
  return kinds;
}

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
  for (const char* t : {"sample", "material", "numerics", "output", "stage"}) top.accept(t);
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
    throw InputError(file_name + ": no stages: add at least one [[stage]] table (see docs/deck.md)");
  const toml::value& stages = root.as_table().at("stage");
  if (!stages.is_array())
    throw InputError(file_name + ":" + std::to_string(stages.location().line()) +
                     ": 'stage' must be an array of tables, written [[stage]]");
  int index = 0;
  bool after_compress = false;
  for (const auto& s : stages.as_array()) {
    deck.stages.push_back(read_stage(s, index++, file_name, deck.sample, deck.material, after_compress));
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
  if (!in) throw InputError(path.string() + ": cannot open the deck file (does it exist?)");
  std::ostringstream os;
  os << in.rdbuf();
  if (in.bad()) throw InputError(path.string() + ": read error");
  return os.str();
}

Deck load_deck(const std::filesystem::path& path) {
  return parse_deck(read_deck_text(path), path.string());
}

}  // namespace granpack
