// Ensembles: the reseeded deck text (io/deck_seed.h), the statistics of an ensemble's samples
// (app/ensemble_summary.h), and the refusals of run_ensemble and summarize_ensemble on every
// rank. The end-to-end run (split ranks, identical files, restart, the options the driver
// refuses) is tests/cli/ensemble.sh.
#include <gtest/gtest.h>

#include <cmath>

#include "granpack/app/ensemble_run.h"
#include "granpack/app/ensemble_summary.h"
#include "granpack/core/error.h"
#include "granpack/io/deck.h"
#include "granpack/io/deck_seed.h"
#include "mpi_world.h"
#include "test_paths.h"

using namespace granpack;

namespace {

const char* kDeck = R"([sample]
dimension = 3
n = 256
diameter = 1e-3
seed = 7   # the deck's own

[material]
density = 2500.0
young_modulus = 70e9
poisson_ratio = 0.3
friction = 0.3
damping = 0.98

[[stage]]
kind = "lattice"
phi = 0.45

[[stage]]
kind = "ed_gas"
collisions_per_grain = 5

[[stage]]
kind = "ed_gas"
collisions_per_grain = 5
seed = 40
)";

std::uint64_t gas_seed(const Deck& d, int index) {
  return std::get<EdGasStage>(d.stages[static_cast<std::size_t>(index)].params).seed;
}

} // namespace

TEST(DeckSeed, SetsSampleSeedAndShiftsEveryStageSeed) {
  const Deck own = parse_deck(kDeck, "deck.toml");
  const Deck d = parse_deck(reseeded_deck_text(kDeck, "deck.toml", 10), "deck.toml");
  EXPECT_EQ(d.sample.seed, 10u);
  EXPECT_EQ(gas_seed(own, 1), 7u + 1000 + 1); // default: [sample] seed + 1000 + index
  EXPECT_EQ(gas_seed(d, 1), 10u + 1000 + 1);
  EXPECT_EQ(gas_seed(own, 2), 40u); // explicit: shifted by 10 - 7
  EXPECT_EQ(gas_seed(d, 2), 43u);
  // The same deck otherwise: material and stages other than their seeds.
  EXPECT_EQ(d.material, own.material);
  EXPECT_EQ(d.stages.size(), own.stages.size());
}

TEST(DeckSeed, OwnSeedGivesTheSameDeckAndTheTextSaysTheSeed) {
  const Deck own = parse_deck(kDeck, "deck.toml");
  const Deck same = parse_deck(reseeded_deck_text(kDeck, "deck.toml", 7), "deck.toml");
  EXPECT_EQ(same.sample, own.sample);
  for (std::size_t i = 0; i < own.stages.size(); ++i)
    EXPECT_EQ(same.stages[i].params, own.stages[i].params);
  const std::string text = reseeded_deck_text(kDeck, "deck.toml", 3);
  EXPECT_NE(text.find("seed = 3  # granpack run --seed 3 (the deck says 7)"), std::string::npos)
      << text;
}

TEST(DeckSeed, DeckWithoutSeedLineGetsOne) {
  std::string text = kDeck;
  text.erase(text.find("seed = 7   # the deck's own\n"),
             std::string("seed = 7   # the deck's own\n").size());
  const Deck d = parse_deck(reseeded_deck_text(text, "deck.toml", 5), "deck.toml");
  EXPECT_EQ(d.sample.seed, 5u);
  EXPECT_EQ(gas_seed(d, 2), 40u + 5 - 1); // the deck's seed was the default 1
}

TEST(DeckSeed, RefusesSeedsItCannotRewrite) {
  // Stages as inline tables: the stage seed shares its line with other keys.
  std::string inline_seed = kDeck;
  inline_seed = "stage = [ { kind = \"lattice\", phi = 0.45 },\n"
                "  { kind = \"ed_gas\", collisions_per_grain = 5, seed = 40 } ]\n" +
                inline_seed.substr(0, inline_seed.find("[[stage]]"));
  ASSERT_NO_THROW(parse_deck(inline_seed, "deck.toml"));
  try {
    reseeded_deck_text(inline_seed, "deck.toml", 5);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("deck.toml:2: cannot change the seed"), std::string::npos)
        << e.what();
  }
  try {
    reseeded_deck_text(kDeck, "deck.toml",
                       9223372036854775807ULL); // stage seed 40 + shift overflows
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("deck.toml:"), std::string::npos) << e.what();
  }
}

TEST(EnsembleSummary, MeanSampleSdAndKOfEveryNumber) {
  std::vector<SampleDocuments> s(4);
  const double phi[] = {0.636, 0.638, 0.637};
  for (int k = 0; k < 3; ++k) {
    s[k].seed = static_cast<std::uint64_t>(k + 1);
    s[k].report = {{"n", 4000},
                   {"deck", "A.toml"},
                   {"stages",
                    {{{"name", "lattice"}, {"phi", 0.45}},
                     {{"name", "compress"}, {"phi", phi[k]}, {"equilibrated", true}}}}};
    nlohmann::json a = {{"z_star", 6.07 + 0.01 * k},
                        {"g_r", {{"g_I", {1.0, 2.0 + k}}}},
                        {"order", {{"1.40", {{"Z", 13.0}}}}}};
    if (k == 2)
      a["only_here"] = 1.5;
    s[k].analyses.emplace_back("A", a);
  }
  s[3].seed = 9; // a sample that did not finish: no report
  const nlohmann::json e = summarize_samples(s);
  EXPECT_EQ(e["K"], 3);
  EXPECT_EQ(e["seeds"], nlohmann::json({1, 2, 3}));
  EXPECT_EQ(e["unfinished"], nlohmann::json({9}));
  const auto& p = e["report"]["/stages/compress/phi"];
  EXPECT_NEAR(p["mean"].get<double>(), 0.637, 1e-15);
  EXPECT_NEAR(p["sd"].get<double>(), 0.001, 1e-12); // K - 1 in the denominator
  EXPECT_EQ(p["K"], 3);
  EXPECT_FALSE(e["report"].contains("/stages/compress/equilibrated")); // booleans are not numbers
  const auto& a = e["analysis"]["A"];
  EXPECT_NEAR(a["/z_star"]["sd"].get<double>(), 0.01, 1e-12);
  EXPECT_EQ(a["/order/1.40/Z"]["sd"].get<double>(), 0.0);
  EXPECT_EQ(a["/g_r/g_I"]["mean"], nlohmann::json({1.0, 3.0})); // curves element-wise
  EXPECT_NEAR(a["/g_r/g_I"]["sd"][1].get<double>(), 1.0, 1e-15);
  EXPECT_EQ(a["/only_here"]["K"], 1);
  EXPECT_TRUE(a["/only_here"]["sd"].is_null());
  EXPECT_EQ(a["/only_here"]["values"], nlohmann::json({nullptr, nullptr, 1.5}));
}

// `granpack run DECK --samples 2 --ranks-per-sample <ranks + 1>`: refused on every rank before
// any work (exit code 2), naming the job's rank count; nothing written.
TEST(EnsembleRefusals, RanksPerSampleMustDivideTheRanks) {
  const int size = test::world_size();
  const auto dir = test::scratch_dir("ensemble_refusals_np" + std::to_string(size));
  if (test::world_rank() == 0)
    std::filesystem::remove_all(dir / "bad2"); // from an earlier run
  MPI_Barrier(MPI_COMM_WORLD);
  EnsembleOptions o;
  o.run.deck = dir / "never_read.toml";
  o.run.output_dir = dir / "bad2";
  o.samples = 2;
  o.ranks_per_sample = size + 1; // divides no rank count
  try {
    run_ensemble(MPI_COMM_WORLD, o);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.exit_code(), kExitBadInput);
    EXPECT_NE(std::string(e.what()).find("--ranks-per-sample " + std::to_string(size + 1) +
                                         ": must divide the " + std::to_string(size) +
                                         " MPI ranks"),
              std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(o.run.output_dir));
}

// `granpack ensemble DIR` of a directory without samples: refused on every rank, saying so.
TEST(EnsembleRefusals, DirectoryWithoutSamples) {
  const auto dir = test::scratch_dir("ensemble_empty_np" + std::to_string(test::world_size()));
  EnsembleSummaryOptions o;
  o.directory = dir;
  try {
    summarize_ensemble(MPI_COMM_WORLD, o);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) { // gathered on every rank by collectively(): an Error with code 2
    EXPECT_EQ(e.exit_code(), kExitBadInput);
    EXPECT_NE(std::string(e.what()).find(dir.string() + ": holds no sample_"), std::string::npos)
        << e.what();
  }
}

TEST(DeckSeed, ReadStageFileTakesTheSampleSeed) {
  const std::string text = R"([sample]
dimension = 3
n = 4000
diameter = 1e-3
seed = 1
[material]
density = 2500.0
young_modulus = 70e9
poisson_ratio = 0.3
friction = 0.3
damping = 0.98
[[stage]]
kind = "read"
file = "out/ens/C/sample_{seed}/A{seed}.h5"
)";
  const auto file_of = [](const Deck& d) { return std::get<ReadStage>(d.stages[0].params).file; };
  EXPECT_EQ(file_of(parse_deck(text, "deck.toml")), "out/ens/C/sample_1/A1.h5");
  EXPECT_EQ(file_of(parse_deck(reseeded_deck_text(text, "deck.toml", 4), "deck.toml")),
            "out/ens/C/sample_4/A4.h5");
}
