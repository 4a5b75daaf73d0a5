// How each stage kind reads its [[stage]] table (io/stage_params.h), and the registry's
// dispatch: the kind names its struct, whose parse() reads the keys.
#include "granpack/io/stage_params.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <string>
#include <utility>

#include "granpack/core/error.h"
#include "granpack/io/deck_reader.h"
#include "granpack/io/stage_table.h"

namespace granpack {

namespace {

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
  c.quench_interval =
      rk.integer_or("quench_interval", 0, Range::non_negative(),
                    "steps between velocity quenches of a static packing (0: never)");
  c.quench_always =
      rk.choice_or("quench_when", "static", {"static", "always"},
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
          if (e.is_string() && e.as_string().str == axis_names[a])
            axis = a;
        if (axis < 0 || c.fixed[axis])
          ok = false;
        else
          c.fixed[axis] = true;
      }
    rk.accept("fixed_axes");
    if (!ok)
      rk.fail("fixed_axes", "= " + toml_text(arr) +
                                ": expected an array of distinct axis names among " +
                                std::string(dim == 3 ? "\"x\", \"y\", \"z\"" : "\"x\", \"y\""));
    int n_fixed = 0;
    for (bool f : c.fixed)
      n_fixed += f;
    if (n_fixed == dim)
      rk.fail("fixed_axes", "fixes every axis: nothing is stress-controlled");
  }
  if (rk.has("stress")) {
    if (rk.has("pressure"))
      rk.fail("stress", "give either pressure (isotropic) or stress (per axis), not both");
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
      rk.fail("stress",
              "= " + toml_text(arr) + ": expected " + std::to_string(dim) +
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
    if (!c.fixed[a])
      sum += c.stress[a], ++controlled;
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

} // namespace

LatticeStage LatticeStage::parse(StageTable& t) {
  LatticeStage s;
  std::string fallback = t.sample.dimension == 3 ? "fcc" : "hex";
  s.lattice = t.reader.choice_or("lattice", fallback, {t.sample.dimension == 3 ? "fcc" : "hex"},
                                 t.sample.dimension == 3 ? "lattice in 3D" : "lattice in 2D");
  double phi_max = t.sample.dimension == 3 ? std::numbers::pi / std::sqrt(18.0)
                                           : std::numbers::pi / std::sqrt(12.0);
  s.phi = t.reader.number("phi", Range{0.0, phi_max, true, false},
                          "solid fraction (at most the close-packed value)");
  if (t.sample.distribution != "monodisperse")
    t.reader.fail("lattice", "a lattice needs [sample] distribution = \"monodisperse\"");
  const std::int64_t per_cell = t.sample.dimension == 3 ? 4 : 2;
  auto cells = t.reader.integers_opt("cells", t.sample.dimension, {1, 1e6}, "unit cells per axis");
  if (cells) {
    std::int64_t prod = per_cell;
    for (auto c : *cells)
      prod *= c;
    if (prod != t.sample.n)
      t.reader.fail("cells", "= " + toml_text(toml::value(*cells)) + " holds " +
                                 std::to_string(prod) +
                                 " grains but [sample] n = " + std::to_string(t.sample.n));
    s.cells = *cells;
  } else {
    // Cubic (3D) or near-square (2D) default when n allows it.
    auto k = static_cast<std::int64_t>(
        std::llround(std::pow(double(t.sample.n) / per_cell, 1.0 / t.sample.dimension)));
    std::int64_t prod = per_cell;
    for (int a = 0; a < t.sample.dimension; ++a)
      prod *= k;
    if (prod != t.sample.n)
      t.reader.fail("cells", "missing: [sample] n = " + std::to_string(t.sample.n) + " is not " +
                                 std::to_string(per_cell) + " k^" +
                                 std::to_string(t.sample.dimension) + "; give cells = [..] with " +
                                 std::to_string(per_cell) + " x product = n");
    s.cells.assign(t.sample.dimension, k);
  }
  return s;
}

RandomStage RandomStage::parse(StageTable& t) {
  // Overlap removal (stages/overlap_removal) stays far from jamming below these values.
  double phi_max = t.sample.dimension == 3 ? 0.55 : 0.70;
  RandomStage rs{t.reader.number("phi", Range{0.0, phi_max, true, false},
                                 "solid fraction of the random placement")};
  rs.placement = t.reader.choice_or("placement", "relax", {"relax", "sequential"},
                                    "the placement (relax: overlaps removed, pairs left "
                                    "touching; sequential: random sequential addition)");
  return rs;
}

CompressStage CompressStage::parse(StageTable& t) {
  CompressStage c;
  read_stress_target(t.reader, t.table, t.sample, t.material.cohesion_force > 0, c);
  read_compress_controls(t.reader, c);
  if (c.inertia_max && !(c.pressure > 0))
    t.reader.fail(
        "inertia_max",
        "needs P > 0 (I = eps_dot sqrt(m / (a P))); at P = 0 cap the rate with strain_rate_max");
  return c;
}

SetStage SetStage::parse(StageTable& t) {
  SetStage s;
  if (t.reader.has("friction"))
    s.friction = t.reader.number("friction", Range::non_negative(), "new friction coefficient");
  if (t.reader.has("damping"))
    s.damping = t.reader.number("damping", Range::half_open(0.0, 1.0), "new damping fraction zeta");
  if (t.reader.has("rolling_damping")) {
    s.rolling_damping = t.reader.number("rolling_damping", Range::half_open(0.0, 1.0),
                                        "new rolling damping zeta_r");
    if (!(t.material.rolling_stiffness > 0))
      t.reader.fail("rolling_damping",
                    "needs rolling resistance: the deck's [material] has no rolling_stiffness > 0");
  }
  if (!s.friction && !s.damping && !s.rolling_damping)
    t.reader.fail("kind",
                  "= \"set\" changes nothing: give friction, damping and/or rolling_damping");
  return s;
}

WriteStage WriteStage::parse(StageTable& t) {
  std::string f = t.reader.string_or("file", "", "HDF5 file name relative to the output directory");
  if (f.empty())
    t.reader.fail("file", "missing required key (HDF5 file name, e.g. \"after_compress.h5\")");
  if (f.find('/') != std::string::npos || f.size() < 4 || f.substr(f.size() - 3) != ".h5")
    t.reader.fail("file",
                  "= \"" + f + "\": must be a plain file name ending in .h5 (no directories)");
  return WriteStage{f};
}

ReadStage ReadStage::parse(StageTable& t) {
  if (t.index != 0)
    t.reader.fail("kind", "= \"read\" must be the first stage (it builds the sample)");
  std::string f = t.reader.string_or("file", "", "configuration file (.h5) written by granpack");
  if (f.empty())
    t.reader.fail("file", "missing required key (a granpack .h5 file, e.g. \"out/A/A.h5\")");
  // "{seed}" is the t.sample's seed: each t.sample of an ensemble reads its own file, e.g. the
  // A.h5 of the same sample of another ensemble (docs/deck.md, "read").
  for (std::size_t at = f.find("{seed}"); at != std::string::npos; at = f.find("{seed}", at))
    f.replace(at, 6, std::to_string(t.sample.seed));
  return ReadStage{f};
}

EdGasStage EdGasStage::parse(StageTable& t) {
  EdGasStage e;
  e.collisions_per_grain = t.reader.number("collisions_per_grain", Range::positive(),
                                           "mean number of collisions per grain (n_coll)");
  e.seed = read_seed(t.reader, t.sample, t.index);
  return e;
}

LsCompressStage LsCompressStage::parse(StageTable& t) {
  LsCompressStage l;
  const double phi_max = t.sample.dimension == 3 ? 0.64 : 0.82;
  l.phi =
      t.reader.number("phi", Range::open(0.0, phi_max), "target solid fraction (below jamming)");
  l.growth_rate = t.reader.number_or("growth_rate", l.growth_rate, Range::positive(),
                                     "d(diameter)/dt in units of the rms velocity");
  l.rescale_every = t.reader.number_or("rescale_every", l.rescale_every, Range::positive(),
                                       "collisions per grain between kinetic-energy resets");
  if (t.reader.has("report_phi")) {
    const toml::value& arr = v_table(t.table, "report_phi");
    t.reader.accept("report_phi");
    l.report_phi.clear();
    bool ok = arr.is_array();
    if (ok)
      for (const auto& e : arr.as_array()) {
        const double x = e.is_floating()  ? e.as_floating()
                         : e.is_integer() ? double(e.as_integer())
                                          : -1;
        ok = ok && x > 0 && x < l.phi && (l.report_phi.empty() || x > l.report_phi.back());
        l.report_phi.push_back(x);
      }
    if (!ok)
      t.reader.fail("report_phi",
                    "= " + toml_text(arr) + ": expected increasing solid fractions below phi");
  } else {
    std::erase_if(l.report_phi, [&](double x) { return x >= l.phi; });
  }
  l.seed = read_seed(t.reader, t.sample, t.index);
  return l;
}

ExpandStage ExpandStage::parse(StageTable& t) {
  return ExpandStage{t.reader.number("factor", Range{1.0, 2.0, true, false},
                                     "homothetic expansion factor lambda, in (1, 2]")};
}

PressureStepsStage PressureStepsStage::parse(StageTable& t) {
  if (!t.after_compress)
    t.reader.fail("kind",
                  "= \"pressure_steps\" needs an earlier compress stage: its pressure is P_0");
  PressureStepsStage ps;
  ps.factor =
      t.reader.number("factor", Range::positive(), "pressure ratio between levels (e.g. 3.1623)");
  if (ps.factor == 1.0)
    t.reader.fail("factor", "= 1: the pressure would not change");
  ps.count = t.reader.integer("count", {1, 1000}, "number of pressure levels");
  ps.write = t.reader.boolean_or("write", true, "write each equilibrated level to <name>_<k>.h5");
  read_compress_controls(t.reader, ps.compress);
  return ps;
}

FixRattlersStage FixRattlersStage::parse(StageTable& t) {
  FixRattlersStage f;
  if (t.reader.has("pressure"))
    f.pressure = t.reader.number("pressure", Range::positive(),
                                 "pressure P of the packing (Pa), the push scale");
  else if (!t.after_compress)
    t.reader.fail("kind",
                  "= \"fix_rattlers\" needs an earlier compress stage (an equilibrated backbone) "
                  "or a `pressure` key (after a read stage)");
  f.force = t.reader.number_or("force", f.force, Range::open(0.0, 1.0), "push magnitude / (a^2 P)");
  f.tolerance = t.reader.number_or("tolerance", f.tolerance, Range::open(0.0, 1.0),
                                   "net force on every rattler / push magnitude at equilibrium");
  f.max_steps = t.reader.integer_or("max_steps", 0, Range::non_negative(), "step limit (0: none)");
  f.seed = read_seed(t.reader, t.sample, t.index);
  return f;
}

AggregateStage AggregateStage::parse(StageTable& t) {
  AggregateStage g;
  g.velocity_ratio = t.reader.number("velocity_ratio", Range::positive(),
                                     "V0/V*: rms velocity of the Maxwell distribution over V* = "
                                     "sqrt(F0 D0 / m) ([GRC]: 9.48)");
  g.max_steps = t.reader.integer_or("max_steps", 0, Range::non_negative(), "step limit (0: none)");
  g.cluster_every = t.reader.integer_or("cluster_every", g.cluster_every, Range::positive(),
                                        "steps between cluster counts");
  g.quench_interval =
      t.reader.integer_or("quench_interval", 0, Range::non_negative(),
                          "steps between velocity quenches once there is one cluster (0: never)");
  g.quench_delay = t.reader.integer_or("quench_delay", 0, Range::non_negative(),
                                       "steps from the first single cluster to the first quench");
  g.tolerance = read_tolerances(t.reader);
  g.seed = read_seed(t.reader, t.sample, t.index);
  return g;
}

StiffenStage StiffenStage::parse(StageTable& t) {
  if (t.material.normal_law != "linear")
    t.reader.fail(
        "kind",
        "= \"stiffen\" ramps the linear law's K_N: needs [material] normal_law = \"linear\"");
  StiffenStage f;
  f.normal_stiffness =
      t.reader.number("normal_stiffness", Range::positive(), "target normal stiffness K_N in N/m");
  f.steps = t.reader.integer("steps", Range::positive(), "time steps of the ramp");
  f.increments =
      t.reader.integer_or("increments", f.increments, Range::closed(1.0, double(f.steps)),
                          "equal geometric factors of the ramp (at most steps)");
  f.scale_rolling =
      t.reader.boolean_or("scale_rolling_stiffness", true, "the rolling stiffness K_r follows K_N");
  read_stress_target(t.reader, t.table, t.sample, t.material.cohesion_force > 0, f.control);
  read_cell_controls(t.reader, f.control);
  if (f.control.inertia_max && !(f.control.pressure > 0))
    t.reader.fail(
        "inertia_max",
        "needs P > 0 (I = eps_dot sqrt(m / (a P))); at P = 0 cap the rate with strain_rate_max");
  return f;
}

DivalentLaunchStage DivalentLaunchStage::parse(StageTable& t) {
  if (t.sample.dimension != 3)
    t.reader.fail("kind", "= \"divalent_launch\" is 3D: [sample] dimension = " +
                              std::to_string(t.sample.dimension));
  if (!(t.material.friction > 0))
    t.reader.fail("kind", "= \"divalent_launch\" needs friction ([material] friction > 0): a "
                          "frictionless grain with two contacts carries no force");
  DivalentLaunchStage d;
  read_stress_target(t.reader, t.table, t.sample, false, d.control);
  read_cell_controls(t.reader, d.control);
  d.pick = t.reader.integer_or("pick", 0, Range::non_negative(),
                               "which divalent grain, by decreasing contact force (0: largest)");
  d.frozen_network = t.reader.boolean_or("frozen_network", false,
                                         "only the pairs in contact at launch may interact");
  d.centrifugal_ratio =
      t.reader.number_or("centrifugal_ratio", d.centrifugal_ratio, Range::open(0.0, 1.0),
                         "m omega0^2 D / |F| ([AR] App. E: 1e-4)");
  d.turns = t.reader.number_or("turns", d.turns, Range::positive(),
                               "turns of the grain's centre about its neighbours' axis");
  d.max_steps = t.reader.integer_or("max_steps", 0, Range::non_negative(), "step limit (0: turns)");
  d.record_every = t.reader.integer_or("record_every", d.record_every, Range::positive(),
                                       "steps between trajectory rows");
  d.collapse_fraction =
      t.reader.number_or("collapse_fraction", d.collapse_fraction, Range::open(0.0, 1.0),
                         "fraction of the launch contacts opened that means a collapse");
  d.energy_factor = t.reader.number_or("energy_factor", d.energy_factor, Range::positive(),
                                       "kinetic energy / launch energy that means a rearrangement");
  d.stop_on = t.reader.choice_or("stop_on", d.stop_on, {"collapse", "rearrangement", "never"},
                                 "what ends the run before its turns");
  d.trajectory = t.reader.string_or("trajectory", d.trajectory,
                                    "trajectory CSV, relative to the output directory");
  return d;
}

namespace {

template <std::size_t... I> std::vector<std::string> kind_names(std::index_sequence<I...>) {
  return {std::string(std::variant_alternative_t<I, StageParams>::kind)...};
}

template <std::size_t... I> constexpr bool kinds_distinct(std::index_sequence<I...>) {
  constexpr std::string_view names[] = {std::variant_alternative_t<I, StageParams>::kind...};
  for (std::size_t a = 0; a < sizeof...(I); ++a)
    for (std::size_t b = a + 1; b < sizeof...(I); ++b)
      if (names[a] == names[b])
        return false;
  return true;
}
constexpr auto kRegistry = std::make_index_sequence<std::variant_size_v<StageParams>>{};
static_assert(kinds_distinct(kRegistry), "two stage kinds of StageParams share a name");

template <std::size_t I = 0> StageParams parse_as(const std::string& kind, StageTable& t) {
  if constexpr (I == std::variant_size_v<StageParams>) {
    GRANPACK_CHECK(false, "stage kind '" << kind << "' is not in the registry StageParams");
  } else {
    using Kind = std::variant_alternative_t<I, StageParams>;
    if (kind == Kind::kind)
      return StageParams(std::in_place_index<I>, Kind::parse(t));
    return parse_as<I + 1>(kind, t);
  }
}

} // namespace

const std::vector<std::string>& stage_kinds() {
  static const std::vector<std::string> kinds = kind_names(kRegistry);
  return kinds;
}

StageParams parse_stage_params(const std::string& kind, StageTable& t) {
  return parse_as(kind, t);
}

} // namespace granpack
