// Deck parsing and validation, and the refusal of every deck of tests/decks/bad/ (BadDeck.*);
// tests/cli/bad_decks.sh keeps one end-to-end case per way in (exit code, message printed once,
// nothing written).
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "granpack/app/run_deck.h"
#include "granpack/core/error.h"
#include "granpack/io/deck.h"
#include "granpack/io/state_parameters.h"
#include "test_paths.h"

using namespace granpack;

namespace {
const char* kGood = R"(
[sample]
dimension = 2
n = 1400
diameter = 1e-4
distribution = "uniform"
seed = 7

[material]
density = 2500.0
normal_law = "linear"
normal_stiffness = 1.0e5
friction = inf
damping = 0.5

[output]
quiet = true

[[stage]]
kind = "compress"
pressure = 100.0
inertia_max = 1e-3

[[stage]]
kind = "set"
friction = 0.15

[[stage]]
kind = "write"
file = "a.h5"
)";

std::string message_of(const std::string& text) {
  try {
    parse_deck(text, "t.toml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "(accepted)";
}
} // namespace

TEST(Deck, ParsesEveryKeyWithDefaults) {
  Deck d = parse_deck(kGood, "good.toml");
  EXPECT_EQ(d.sample.dimension, 2);
  EXPECT_EQ(d.sample.n, 1400);
  EXPECT_EQ(d.sample.distribution, "uniform");
  EXPECT_DOUBLE_EQ(d.sample.min_diameter_ratio, 0.5);
  EXPECT_EQ(d.sample.seed, 7u);
  EXPECT_EQ(d.material.normal_law, "linear");
  EXPECT_TRUE(std::isinf(d.material.friction));
  EXPECT_DOUBLE_EQ(d.material.tangential_stiffness_ratio, 1.0);
  EXPECT_DOUBLE_EQ(d.numerics.time_step_fraction, 0.02);
  EXPECT_FALSE(d.numerics.load_balance);
  EXPECT_DOUBLE_EQ(d.numerics.load_balance_threshold, 1.1);
  EXPECT_EQ(d.numerics.halo, "shared_memory");
  EXPECT_TRUE(d.output.quiet);
  ASSERT_EQ(d.stages.size(), 3u);
  const auto& c = std::get<CompressStage>(d.stages[0].params);
  EXPECT_DOUBLE_EQ(c.pressure, 100.0);
  ASSERT_TRUE(c.inertia_max.has_value());
  EXPECT_DOUBLE_EQ(c.tolerance.kinetic, 1e-8);
  EXPECT_EQ(d.stages[1].name, "set");
  EXPECT_DOUBLE_EQ(*std::get<SetStage>(d.stages[1].params).friction, 0.15);
  EXPECT_EQ(std::get<WriteStage>(d.stages[2].params).file, "a.h5");
  EXPECT_EQ(d.text, kGood);
}

// The registry (io/stage_params.h) lists the kinds in documentation order (an unknown kind is
// refused with this list: tests/decks/bad/unknown_stage.toml).
TEST(Deck, StageKindsAreTheRegistryInDocumentationOrder) {
  const std::vector<std::string> documented = {
      "lattice", "random",    "read",           "ed_gas",         "ls_compress",
      "expand",  "compress",  "pressure_steps", "fix_rattlers",   "set",
      "write",   "aggregate", "stiffen",        "divalent_launch"};
  EXPECT_EQ(stage_kinds(), documented);
}

TEST(Deck, RejectionsNameTheKeyValueAndWhatIsAllowed) {
  auto replaced = [](std::string t, const std::string& from, const std::string& to) {
    auto pos = t.find(from);
    EXPECT_NE(pos, std::string::npos) << from;
    return t.replace(pos, from.size(), to);
  };
  auto with = [&](const std::string& from, const std::string& to) {
    return replaced(kGood, from, to);
  };
  EXPECT_NE(message_of(with("damping = 0.5", "damping = -0.5"))
                .find("[material] damping: = -0.5 is out of range"),
            std::string::npos);
  EXPECT_NE(message_of(with("normal_stiffness = 1.0e5", "young_modulus = 1.0e5"))
                .find("normal_stiffness: missing required key"),
            std::string::npos);
  EXPECT_NE(message_of(with("inertia_max = 1e-3", "inertia_max = \"fast\""))
                .find("[stage[0] (compress)] inertia_max: = \"fast\" is a string"),
            std::string::npos);
  EXPECT_NE(
      message_of(with("file = \"a.h5\"", "file = \"../a.h5\"")).find("must be a plain file name"),
      std::string::npos);
  EXPECT_NE(
      message_of(with("kind = \"set\"\nfriction = 0.15", "kind = \"set\"")).find("changes nothing"),
      std::string::npos);
  EXPECT_NE(message_of(with("seed = 7", "seed = 7\nseeed = 8"))
                .find("t.toml:8: [sample] seeed: unknown key"),
            std::string::npos);
  EXPECT_NE(message_of(with("[sample]", "sample = 3\n[sampl]")).find("'sample' must be a table"),
            std::string::npos);
  // [GRC] parts: both cohesion keys or neither, a rolling friction needs a stiffness, finite.
  EXPECT_NE(message_of(with("damping = 0.5", "damping = 0.5\ncohesion_force = 1e-3"))
                .find("[material] cohesion_range: cohesion needs both"),
            std::string::npos);
  EXPECT_NE(message_of(with("damping = 0.5", "damping = 0.5\ncohesion_range = 1e-7"))
                .find("[material] cohesion_force: cohesion needs both"),
            std::string::npos);
  EXPECT_NE(message_of(
                with("damping = 0.5", "damping = 0.5\ncohesion_force = inf\ncohesion_range = 1e-7"))
                .find("[material] cohesion_force: = inf is out of range"),
            std::string::npos);
  EXPECT_NE(message_of(with("damping = 0.5", "damping = 0.5\nrolling_friction = 1e-6"))
                .find("[material] rolling_stiffness: rolling_friction > 0 needs"),
            std::string::npos);
  EXPECT_NE(message_of(with("damping = 0.5", "damping = 0.5\nrolling_stiffness = -1.0"))
                .find("[material] rolling_stiffness: = -1.0 is out of range"),
            std::string::npos);
  // Walton's rescaling is a property of the Hertz law's K_T(N); the linear law has none.
  EXPECT_NE(message_of(with("damping = 0.5", "damping = 0.5\nwalton_rescaling = false"))
                .find("[material] walton_rescaling: only applies to normal_law = \"hertz\""),
            std::string::npos);
  const std::string hertz = with("normal_law = \"linear\"\nnormal_stiffness = 1.0e5",
                                 "young_modulus = 70e9\npoisson_ratio = 0.3");
  EXPECT_TRUE(parse_deck(hertz, "t.toml").material.walton_rescaling);
  const Deck no_walton = parse_deck(
      replaced(hertz, "damping = 0.5", "damping = 0.5\nwalton_rescaling = false"), "t.toml");
  EXPECT_FALSE(no_walton.material.walton_rescaling);
  EXPECT_FALSE(contact_law_params(no_walton.material).walton_rescaling);
  // Load balancing: a threshold of 1 would move the planes at every rebuild of a balanced run.
  EXPECT_NE(message_of(with("[output]", "[numerics]\nload_balance = true\n"
                                        "load_balance_threshold = 1.0\n[output]"))
                .find("[numerics] load_balance_threshold: = 1.0 is out of range"),
            std::string::npos);
  EXPECT_NE(message_of(with("[output]", "[numerics]\nload_balance = 1\n[output]"))
                .find("[numerics] load_balance: = 1 is an integer"),
            std::string::npos);
  const Deck lb = parse_deck(with("[output]", "[numerics]\nload_balance = true\n"
                                              "load_balance_threshold = 1.25\n[output]"),
                             "t.toml");
  EXPECT_TRUE(lb.numerics.load_balance);
  EXPECT_DOUBLE_EQ(lb.numerics.load_balance_threshold, 1.25);
  // The halo's transport: one of two words (tests/decks/bad/halo_unknown.toml end to end).
  EXPECT_NE(message_of(with("[output]", "[numerics]\nhalo = \"shm\"\n[output]"))
                .find("[numerics] halo: = \"shm\" is not allowed: the halo's transport must be "
                      "one of \"messages\", \"shared_memory\""),
            std::string::npos);
  EXPECT_NE(message_of(with("[output]", "[numerics]\nhalo = true\n[output]"))
                .find("[numerics] halo: = true is a boolean, expected a string"),
            std::string::npos);
  EXPECT_EQ(parse_deck(with("[output]", "[numerics]\nhalo = \"shared_memory\"\n[output]"), "t.toml")
                .numerics.halo,
            "shared_memory");
}

TEST(Deck, CohesionAndRollingResistanceKeys) {
  std::string t = kGood;
  t.replace(t.find("damping = 0.5"), 13,
            "damping = 0.5\ncohesion_force = 2e-3\ncohesion_range = 1e-7\n"
            "rolling_stiffness = 1e-4\nrolling_friction = inf");
  const Deck d = parse_deck(t, "c.toml");
  EXPECT_DOUBLE_EQ(d.material.cohesion_force, 2e-3);
  EXPECT_DOUBLE_EQ(d.material.cohesion_range, 1e-7);
  EXPECT_DOUBLE_EQ(d.material.rolling_stiffness, 1e-4);
  EXPECT_TRUE(std::isinf(d.material.rolling_friction));
  const Deck plain = parse_deck(kGood, "good.toml");
  EXPECT_EQ(plain.material.cohesion_force, 0.0);
  EXPECT_EQ(plain.material.rolling_stiffness, 0.0);
}

// [GRC] method 2: compress at P* = 0 needs cohesion, a strain-rate cap replaces the inertia
// cap there, and `stiffen` (series B) ramps the linear law's K_N; replayed_parameters (the
// reading of files written before /parameters existed) replays it.
TEST(Deck, MethodTwoKeys) {
  std::string cohesive = kGood;
  cohesive.replace(
      cohesive.find("damping = 0.5"), 13,
      "damping = 0.5\ncohesion_force = 2e-3\ncohesion_range = 1e-7\nrolling_stiffness = 1e-4");
  auto stage = [](std::string t, const std::string& from, const std::string& to) {
    t.replace(t.find(from), from.size(), to);
    return t;
  };
  // P = 0: refused without cohesion, and with an inertia cap; the strain-rate cap is read.
  EXPECT_NE(message_of(stage(kGood, "pressure = 100.0\ninertia_max = 1e-3", "pressure = 0.0"))
                .find("pressure: = 0.0 is out of range"),
            std::string::npos);
  EXPECT_NE(message_of(stage(cohesive, "pressure = 100.0", "pressure = 0.0"))
                .find("inertia_max: needs P > 0"),
            std::string::npos);
  const Deck p0 = parse_deck(stage(cohesive, "pressure = 100.0\ninertia_max = 1e-3",
                                   "pressure = 0\nstrain_rate_max = 35.7"),
                             "p0.toml");
  const auto& c = std::get<CompressStage>(p0.stages[0].params);
  EXPECT_EQ(c.pressure, 0.0);
  EXPECT_EQ(c.strain_rate_max, 35.7);
  EXPECT_FALSE(c.inertia_max);
  EXPECT_NE(message_of(stage(kGood, "inertia_max = 1e-3", "strain_rate_max = -1"))
                .find("strain_rate_max: = -1 is out of range"),
            std::string::npos);

  // stiffen: target, steps, increments <= steps, the stress target; replayed for old files.
  const std::string stiff =
      "[[stage]]\nkind = \"stiffen\"\nnormal_stiffness = 1e7\nsteps = 1000\nincrements = "
      "10\npressure = 0\ncell_mass = 0.3\n\n[[stage]]\nkind = \"write\"";
  const Deck d = parse_deck(stage(cohesive, "[[stage]]\nkind = \"write\"", stiff), "s.toml");
  const auto& f = std::get<StiffenStage>(d.stages[2].params);
  EXPECT_EQ(f.normal_stiffness, 1e7);
  EXPECT_EQ(f.steps, 1000);
  EXPECT_EQ(f.increments, 10);
  EXPECT_TRUE(f.scale_rolling);
  EXPECT_EQ(f.control.pressure, 0.0);
  EXPECT_EQ(f.control.cell_mass, 0.3);
  const StateParameters at0 = replayed_parameters(d, 0), at1 = replayed_parameters(d, 1),
                        at2 = replayed_parameters(d, 2);
  EXPECT_EQ(at1.contact_law.k_n, 1e5);
  EXPECT_EQ(at1.contact_law.friction, 0.15); // the set stage
  EXPECT_EQ(at2.contact_law.k_n, 1e7);
  EXPECT_DOUBLE_EQ(at2.contact_law.rolling_stiffness, 1e-2); // K_r follows K_N (x 100)
  // The stress target: the compress stage's from its end on; stiffen keeps it.
  EXPECT_EQ(at0.stress_target.stage, 0);
  EXPECT_EQ(at0.stress_target.stress, std::vector<double>(2, 100.0)); // 2D
  EXPECT_EQ(at0.stress_target.pressure, 100.0);
  EXPECT_EQ(at2.stress_target, at0.stress_target);
  EXPECT_NE(message_of(stage(cohesive, "[[stage]]\nkind = \"write\"",
                             stage(stiff, "increments = 10", "increments = 2000")))
                .find("increments: = 2000 is out of range"),
            std::string::npos);
  EXPECT_NE(
      message_of(stage(cohesive, "[[stage]]\nkind = \"write\"", stage(stiff, "steps = 1000\n", "")))
          .find("steps"),
      std::string::npos);
  EXPECT_NE(message_of(stage(cohesive, "[[stage]]\nkind = \"write\"",
                             stage(stiff, "cell_mass = 0.3", "tolerance_force = 1e-4")))
                .find("tolerance_force"),
            std::string::npos); // not a stiffen key
  EXPECT_NE(message_of(stage(kGood, "[[stage]]\nkind = \"write\"",
                             stage(stiff, "pressure = 0", "pressure = 0.0")))
                .find("pressure: = 0.0 is out of range"),
            std::string::npos); // P = 0 needs cohesion

  // set rolling_damping: an aggregation without zeta_r, the stages after it with it. Refused
  // without rolling resistance; replayed from the set stage on.
  EXPECT_NE(message_of(stage(kGood, "friction = 0.15", "rolling_damping = 0.1"))
                .find("rolling_damping: needs rolling resistance"),
            std::string::npos);
  EXPECT_NE(message_of(stage(cohesive, "friction = 0.15", "rolling_damping = 1.0"))
                .find("rolling_damping: = 1.0 is out of range"),
            std::string::npos);
  const Deck zr =
      parse_deck(stage(cohesive, "friction = 0.15", "rolling_damping = 0.1"), "zr.toml");
  EXPECT_EQ(*std::get<SetStage>(zr.stages[1].params).rolling_damping, 0.1);
  EXPECT_FALSE(std::get<SetStage>(zr.stages[1].params).friction);
  EXPECT_EQ(replayed_parameters(zr, 0).contact_law.rolling_damping, 0.0); // the [material]'s
  EXPECT_EQ(replayed_parameters(zr, 1).contact_law.rolling_damping, 0.1);
  EXPECT_EQ(replayed_parameters(zr, 1).contact_law.friction,
            replayed_parameters(zr, 0).contact_law.friction);

  // aggregate: quench_interval (0 by default) is read and must not be negative.
  const std::string agg = "[[stage]]\nkind = \"aggregate\"\nvelocity_ratio = 9.48\nquench_interval "
                          "= 20000\n\n[[stage]]\nkind = \"write\"";
  const Deck q = parse_deck(stage(cohesive, "[[stage]]\nkind = \"write\"", agg), "q.toml");
  EXPECT_EQ(std::get<AggregateStage>(q.stages[2].params).quench_interval, 20000);
  EXPECT_EQ(std::get<AggregateStage>(parse_deck(stage(cohesive, "[[stage]]\nkind = \"write\"",
                                                      stage(agg, "quench_interval = 20000\n", "")),
                                                "q0.toml")
                                         .stages[2]
                                         .params)
                .quench_interval,
            0);
  EXPECT_NE(message_of(stage(cohesive, "[[stage]]\nkind = \"write\"", stage(agg, "20000", "-5")))
                .find("quench_interval: = -5 is out of range"),
            std::string::npos);
  // compress: quench_when is "static" by default, "always" on request, nothing else.
  EXPECT_FALSE(std::get<CompressStage>(parse_deck(kGood, "c.toml").stages[0].params).quench_always);
  const Deck qa =
      parse_deck(stage(kGood, "pressure = 100.0",
                       "pressure = 100.0\nquench_interval = 1000\nquench_when = \"always\""),
                 "qa.toml");
  EXPECT_TRUE(std::get<CompressStage>(qa.stages[0].params).quench_always);
  EXPECT_NE(
      message_of(stage(kGood, "pressure = 100.0", "pressure = 100.0\nquench_when = \"never\""))
          .find("quench_when"),
      std::string::npos);
  // quench_delay likewise (0 by default: quenches from the first single cluster).
  EXPECT_EQ(std::get<AggregateStage>(q.stages[2].params).quench_delay, 0);
  const std::string delayed =
      stage(agg, "quench_interval = 20000\n", "quench_interval = 20000\nquench_delay = 450000\n");
  EXPECT_EQ(std::get<AggregateStage>(
                parse_deck(stage(cohesive, "[[stage]]\nkind = \"write\"", delayed), "qd.toml")
                    .stages[2]
                    .params)
                .quench_delay,
            450000);
  EXPECT_NE(
      message_of(stage(cohesive, "[[stage]]\nkind = \"write\"", stage(delayed, "450000", "-1")))
          .find("quench_delay: = -1 is out of range"),
      std::string::npos);
}

TEST(Deck, PerAxisStressAndFixedAxes) {
  std::string t = kGood;
  t.replace(t.find("pressure = 100.0"), 16, "stress = [100.0, 300]\nfixed_axes = [\"x\"]");
  Deck d = parse_deck(t, "aniso.toml");
  const auto& c = std::get<CompressStage>(d.stages[0].params);
  EXPECT_EQ(c.stress, (std::vector<double>{100.0, 300.0}));
  EXPECT_EQ(c.fixed, (std::vector<bool>{true, false}));
  EXPECT_DOUBLE_EQ(c.pressure, 300.0); // mean over the stress-controlled axes
  std::string both = t;
  both.replace(both.find("stress = ["), 0, "pressure = 5.0\n");
  EXPECT_NE(message_of(both).find("either pressure"), std::string::npos);
  std::string all_fixed = t;
  all_fixed.replace(all_fixed.find("[\"x\"]"), 5, "[\"x\", \"y\"]");
  EXPECT_NE(message_of(all_fixed).find("nothing is stress-controlled"), std::string::npos);
  std::string z_in_2d = t;
  z_in_2d.replace(z_in_2d.find("[\"x\"]"), 5, "[\"z\"]");
  EXPECT_NE(message_of(z_in_2d).find("distinct axis names among \"x\", \"y\""), std::string::npos);
}

TEST(Deck, EveryShippedDeckIsValid) {
  int count = 0;
  for (const auto& e :
       std::filesystem::recursive_directory_iterator(test::source_dir() / "jobs" / "decks")) {
    if (e.path().extension() != ".toml")
      continue;
    EXPECT_NO_THROW(load_deck(e.path())) << e.path();
    ++count;
  }
  EXPECT_GE(count, 1);
}

// The decks of tests/decks/bad/, each refused as `granpack run` refuses it before any work
// (load_deck_collectively: read on rank 0, broadcast, validated on every rank), with an
// InputError (exit code 2) whose message matches the deck's first line "# expect: REGEX"
// (line by line, as grep -E matches it; the patterns use only syntax that grep -E and
// std::regex's ECMAScript grammar read alike): the file and line, the key with its table path,
// the value and what is allowed. Every rank must throw it (validation stops all ranks
// together). tests/cli/bad_decks.sh runs unknown_key end to end.
namespace {
const std::vector<std::string> kBadDecks = {"divalent_frictionless",
                                            "ed_gas_missing",
                                            "expand_shrinks",
                                            "halo_unknown",
                                            "lattice_count",
                                            "ls_above_jamming",
                                            "missing_key",
                                            "n_zero",
                                            "negative_mu",
                                            "no_stage",
                                            "phi_above_one",
                                            "placement_unknown",
                                            "poisson_range",
                                            "pressure_steps_first",
                                            "read_not_first",
                                            "syntax_error",
                                            "unknown_key",
                                            "unknown_stage",
                                            "unknown_table",
                                            "wrong_type",
                                            "zeta_one"};

std::filesystem::path bad_deck_dir() {
  return test::source_dir() / "tests" / "decks" / "bad";
}

/// REGEX of the deck's first line "# expect: REGEX", or "" without one.
std::string expectation_of(const std::filesystem::path& deck) {
  std::ifstream in(deck);
  std::string first;
  std::getline(in, first);
  const std::string tag = "# expect: ";
  return first.rfind(tag, 0) == 0 ? first.substr(tag.size()) : std::string();
}

/// grep -Eq: does some line of `text` hold a match of the regular expression?
bool some_line_matches(const std::string& text, const std::string& pattern) {
  const std::regex re(pattern);
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);)
    if (std::regex_search(line, re))
      return true;
  return false;
}
} // namespace

class BadDeck : public testing::TestWithParam<std::string> {};

TEST_P(BadDeck, RefusedNamingTheFileTheKeyAndWhatIsAllowed) {
  const std::filesystem::path deck = bad_deck_dir() / (GetParam() + ".toml");
  const std::string expect = expectation_of(deck);
  ASSERT_FALSE(expect.empty()) << deck << " has no first line '# expect: REGEX'";
  try {
    load_deck_collectively(MPI_COMM_WORLD, deck, std::nullopt);
    ADD_FAILURE() << deck << " was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.exit_code(), kExitBadInput);
    EXPECT_TRUE(some_line_matches(e.what(), expect))
        << "the message\n  " << e.what() << "\ndoes not match /" << expect << "/";
  }
}

INSTANTIATE_TEST_SUITE_P(Decks, BadDeck, testing::ValuesIn(kBadDecks),
                         [](const testing::TestParamInfo<std::string>& p) { return p.param; });

// A deck file that does not exist is bad input too, refused on every rank before any work
// (tests/cli/bad_decks.sh ran it end to end before).
TEST(BadDeckFile, MissingFileIsRefusedOnEveryRank) {
  const auto missing = bad_deck_dir() / "nope.toml";
  try {
    load_deck_collectively(MPI_COMM_WORLD, missing, std::nullopt);
    ADD_FAILURE() << missing << " was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.exit_code(), kExitBadInput);
    EXPECT_TRUE(some_line_matches(e.what(), "nope.toml: cannot open the deck file")) << e.what();
  }
}

// A deck added to tests/decks/bad/ is checked too: the list above is the directory.
TEST(BadDecks, TheListIsTheDirectory) {
  std::vector<std::string> found;
  for (const auto& e : std::filesystem::directory_iterator(bad_deck_dir()))
    if (e.path().extension() == ".toml")
      found.push_back(e.path().stem().string());
  std::sort(found.begin(), found.end());
  std::vector<std::string> listed = kBadDecks;
  std::sort(listed.begin(), listed.end());
  EXPECT_EQ(found, listed);
}
