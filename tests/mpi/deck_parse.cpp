// Deck parsing and validation (the end-to-end exit-code checks are in tests/cli/bad_decks.sh).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "granpack/core/error.h"
#include "granpack/io/deck.h"
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
}  // namespace

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

TEST(Deck, RejectionsNameTheKeyValueAndWhatIsAllowed) {
  std::string good = kGood;
  auto with = [&](const std::string& from, const std::string& to) {
    std::string t = good;
    auto pos = t.find(from);
    EXPECT_NE(pos, std::string::npos) << from;
    return t.replace(pos, from.size(), to);
  };
  EXPECT_NE(message_of(with("damping = 0.5", "damping = -0.5")).find("[material] damping: = -0.5 is out of range"), std::string::npos);
  EXPECT_NE(message_of(with("normal_stiffness = 1.0e5", "young_modulus = 1.0e5")).find("normal_stiffness: missing required key"), std::string::npos);
  EXPECT_NE(message_of(with("inertia_max = 1e-3", "inertia_max = \"fast\"")).find("[stage[0] (compress)] inertia_max: = \"fast\" is a string"), std::string::npos);
  EXPECT_NE(message_of(with("file = \"a.h5\"", "file = \"../a.h5\"")).find("must be a plain file name"), std::string::npos);
  EXPECT_NE(message_of(with("kind = \"set\"\nfriction = 0.15", "kind = \"set\"")).find("changes nothing"), std::string::npos);
  EXPECT_NE(message_of(with("seed = 7", "seed = 7\nseeed = 8")).find("t.toml:8: [sample] seeed: unknown key"), std::string::npos);
  EXPECT_NE(message_of(with("[sample]", "sample = 3\n[sampl]")).find("'sample' must be a table"), std::string::npos);
  // [GRC] parts: both cohesion keys or neither, a rolling friction needs a stiffness, finite.
  EXPECT_NE(message_of(with("damping = 0.5", "damping = 0.5\ncohesion_force = 1e-3")).find("[material] cohesion_range: cohesion needs both"), std::string::npos);
  EXPECT_NE(message_of(with("damping = 0.5", "damping = 0.5\ncohesion_range = 1e-7")).find("[material] cohesion_force: cohesion needs both"), std::string::npos);
  EXPECT_NE(message_of(with("damping = 0.5", "damping = 0.5\ncohesion_force = inf\ncohesion_range = 1e-7")).find("[material] cohesion_force: = inf is out of range"), std::string::npos);
  EXPECT_NE(message_of(with("damping = 0.5", "damping = 0.5\nrolling_friction = 1e-6")).find("[material] rolling_stiffness: rolling_friction > 0 needs"), std::string::npos);
  EXPECT_NE(message_of(with("damping = 0.5", "damping = 0.5\nrolling_stiffness = -1.0")).find("[material] rolling_stiffness: = -1.0 is out of range"), std::string::npos);
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

TEST(Deck, PerAxisStressAndFixedAxes) {
  std::string t = kGood;
  t.replace(t.find("pressure = 100.0"), 16, "stress = [100.0, 300]\nfixed_axes = [\"x\"]");
  Deck d = parse_deck(t, "aniso.toml");
  const auto& c = std::get<CompressStage>(d.stages[0].params);
  EXPECT_EQ(c.stress, (std::vector<double>{100.0, 300.0}));
  EXPECT_EQ(c.fixed, (std::vector<bool>{true, false}));
  EXPECT_DOUBLE_EQ(c.pressure, 300.0);  // mean over the stress-controlled axes
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
  for (const auto& e : std::filesystem::recursive_directory_iterator(test::source_dir() / "jobs" / "decks")) {
    if (e.path().extension() != ".toml") continue;
    EXPECT_NO_THROW(load_deck(e.path())) << e.path();
    ++count;
  }
  EXPECT_GE(count, 1);
}
