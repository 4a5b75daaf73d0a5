// The parts of a checkpoint beyond the grains: exact doubles, /run_state parsing, and the
// deck comparison that refuses unsafe restarts.
#include <gtest/gtest.h>

#include <mpi.h>

#include <bit>
#include <cmath>
#include <filesystem>
#include <limits>

#include "granpack/core/error.h"
#include "granpack/engine/checkpoint.h"
#include "granpack/io/hdf5_store.h"
#include "granpack/io/report.h"

namespace granpack {
namespace {

TEST(CheckpointState, ExactDoublesRoundTripBitForBit) {
  for (double v : {0.1, -0.0, 1e-300, 6.02214076e23, std::numeric_limits<double>::infinity(),
                   std::numeric_limits<double>::denorm_min()}) {
    const double back = exact_double(exact(v));
    EXPECT_EQ(std::bit_cast<std::uint64_t>(back), std::bit_cast<std::uint64_t>(v)) << v;
  }
  EXPECT_THROW(exact_double(nlohmann::json("0x12")), std::exception);
}

TEST(CheckpointState, GarbageRunStateIsAnInputErrorNamingTheFile) {
  try {
    parse_run_state("{\"format\": 1}", "dir/checkpoint.h5");
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("dir/checkpoint.h5"), std::string::npos);
  }
  EXPECT_THROW(parse_run_state("not json", "f.h5"), InputError);
}

// The completed stages' entries travel in checkpoints as report.json text: the time split and
// the MD step classes come back whole, and an entry written before they existed still reads.
TEST(CheckpointState, StageEntriesKeepTheirTimingAndOldOnesRead) {
  StageReport r;
  r.name = r.kind = "compress";
  r.steps = 30;
  r.wall_seconds = 2.5;
  r.wall_split = WallSplit{0.5, 0.25, 0.125, 0.0625, 0.75, 0.0, 0.8125};
  r.md_classes = StepClasses{1.0, {20, 20 * 256, 1.5}, {10, 10 * 256, 0.0}};
  const StageReport back = stage_report_from_json(stage_report_json(r));
  ASSERT_TRUE(back.wall_split && back.md_classes);
  EXPECT_EQ(back.wall_split->io, 0.75);
  EXPECT_EQ(back.wall_split->other, 0.8125);
  EXPECT_EQ(back.wall_split->listed() + back.wall_split->other, r.wall_seconds);
  EXPECT_EQ(back.md_classes->dense.particle_steps, 20 * 256);
  EXPECT_EQ(back.md_classes->dense.rate(), 20 * 256 / 1.5);
  EXPECT_FALSE(back.md_classes->loose.rate()); // no seconds: written as null
  EXPECT_EQ(stage_report_json(back), stage_report_json(r));
  const StageReport old = stage_report_from_json(
      R"({"name": "c", "kind": "compress", "steps": 3, "time": 0.1, "values": {},
          "wall_seconds": 1.0})");
  EXPECT_FALSE(old.wall_split || old.md_classes || old.phase_seconds);
}

const char* kDeck = R"(
[sample]
dimension = 3
n = 32
diameter = 1.0e-3
[material]
density = 2500.0
young_modulus = 2.88e8
poisson_ratio = 0.3
friction = 0.3
damping = 0.98
[[stage]]
kind = "lattice"
lattice = "fcc"
phi = 0.5
cells = [2, 2, 2]
[[stage]]
kind = "compress"
pressure = 1.0e4
[[stage]]
kind = "write"
file = "a.h5"
)";

std::string message_of(const Deck& a, const Deck& b, const RunState& s, bool allow) {
  try {
    check_restart_deck(a, b, s, allow, "ck.h5");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(CheckpointState, OnlyOutputAndWithTheFlagLaterStagesMayChange) {
  const Deck a = parse_deck(kDeck, "a.toml");
  RunState s;
  s.stage_index = 1;
  s.mid_stage = true; // inside the compress stage
  std::string text = kDeck;
  EXPECT_EQ(message_of(a, parse_deck(text + "[output]\nlog_every = 7\n", "b.toml"), s, false), "");
  const std::string friction = message_of(
      a,
      parse_deck(std::string(kDeck).replace(text.find("friction = 0.3"), 14, "friction = 0.4"),
                 "b.toml"),
      s, false);
  EXPECT_NE(friction.find("[material]"), std::string::npos) << friction;
  // The stage in progress may not change, even with the flag.
  const std::string p =
      std::string(kDeck).replace(text.find("pressure = 1.0e4"), 16, "pressure = 2.0e4");
  const std::string in_progress = message_of(a, parse_deck(p, "b.toml"), s, true);
  EXPECT_NE(in_progress.find("stage[1]"), std::string::npos) << in_progress;
  // A later stage may, with the flag only.
  const std::string w = std::string(kDeck).replace(text.find("a.h5"), 4, "b.h5");
  EXPECT_NE(message_of(a, parse_deck(w, "b.toml"), s, false).find("allow-deck-change"),
            std::string::npos);
  EXPECT_EQ(message_of(a, parse_deck(w, "b.toml"), s, true), "");
}

} // namespace
} // namespace granpack

namespace granpack {
namespace {

// Regression: /run_state whose text differs between ranks (it once held each rank's own
// clock) made the collective dataset creation inconsistent and corrupted contact rows.
// The file must hold rank 0's text and every contact intact.
TEST(CheckpointState, RunStateDifferingBetweenRanksLeavesAValidFile) {
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  Configuration<3> c;
  c.cell.length = Vec<3>::Constant(1e-2);
  c.cell.rate = Vec<3>::Zero();
  const GlobalId base = 10 * rank;
  for (GlobalId k = 0; k < 4; ++k) {
    Particle<3> p;
    p.id = base + k;
    p.radius = 5e-4;
    p.mass = 1e-6;
    p.inertia = 1e-13;
    p.position = Vec<3>::Constant(0.1 + 0.2 * double(k));
    c.particles.add_owned(p);
  }
  for (GlobalId k = 0; k + 1 < 4; ++k) {
    ContactState<3> s;
    s.normal_force = 1.0 + double(base + k);
    s.age = 7 + base + k;
    c.contacts.insert(ContactKey{base + k, base + k + 1}, s);
  }
  c.meta.deck_text = "deck";
  c.meta.kind = "checkpoint";
  c.meta.run_state = "{\"rank\": \"" + std::string(std::size_t(5 + 40 * rank), 'x') + "\"}";
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / "granpack_run_state_test.h5";
  write_configuration<3>(MPI_COMM_WORLD, file, c);
  const FileMeta meta = read_file_meta(MPI_COMM_SELF, file);
  EXPECT_EQ(meta.run_state, "{\"rank\": \"xxxxx\"}");
  Configuration<3> back = read_configuration<3>(MPI_COMM_SELF, file);
  ASSERT_EQ(back.contacts.size(), std::size_t(3 * size));
  for (std::size_t k = 0; k < back.contacts.size(); ++k) {
    const ContactKey key = back.contacts.key(k);
    EXPECT_EQ(key.second, key.first + 1);
    EXPECT_EQ(back.contacts.state(k).normal_force, 1.0 + double(key.first));
    EXPECT_EQ(back.contacts.state(k).age, 7 + key.first);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  if (rank == 0)
    std::filesystem::remove(file);
}

} // namespace
} // namespace granpack

namespace granpack {
namespace {

/// A few grains on each rank and one contact, for files written by the tests below.
Configuration<3> small_configuration(int rank) {
  Configuration<3> c;
  c.cell.length = Vec<3>::Constant(1e-2);
  c.cell.rate = Vec<3>::Zero();
  for (GlobalId k = 0; k < 2; ++k) {
    Particle<3> p;
    p.id = 2 * rank + k;
    p.radius = 5e-4;
    p.mass = 1e-6;
    p.inertia = 1e-13;
    p.position = Vec<3>::Constant(0.1 + 0.3 * double(k));
    c.particles.add_owned(p);
  }
  c.contacts.insert(ContactKey{2 * rank, 2 * rank + 1}, ContactState<3>{});
  c.meta.deck_text = kDeck;
  return c;
}

// Every file a run writes carries the contact law and stress target in force (/parameters):
// they come back exactly, inf included, on any reader; a file without the group reads as one.
TEST(CheckpointState, ParametersRoundTripBitForBit) {
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  StateParameters p;
  p.contact_law.normal = NormalLawKind::kLinear;
  p.contact_law.k_n = 1.2345678901234567e7;
  p.contact_law.tangential = TangentialStiffnessKind::kRatio;
  p.contact_law.k_t_ratio = 0.7;
  p.contact_law.walton_rescaling = false;
  p.contact_law.damping_ratio = 0.98;
  p.contact_law.friction = std::numeric_limits<double>::infinity();
  p.contact_law.cohesion_force = 1.0;
  p.contact_law.cohesion_range = 1e-6;
  p.contact_law.rolling_stiffness = 1e-3;
  p.contact_law.rolling_friction = 5e-6;
  p.contact_law.rolling_damping = 0.8;
  p.stress_target = StressTarget{4, {10.0, 0.1 + 0.2, 30.0}, {false, true, false}, 20.0};
  const auto dir = std::filesystem::temp_directory_path();
  const std::filesystem::path with = dir / "granpack_parameters_test.h5",
                              without = dir / "granpack_no_parameters_test.h5",
                              unset = dir / "granpack_unset_target_test.h5";
  Configuration<3> c = small_configuration(rank);
  c.meta.parameters = p;
  write_configuration<3>(MPI_COMM_WORLD, with, c);
  c.meta.parameters->stress_target = StressTarget{};
  write_configuration<3>(MPI_COMM_WORLD, unset, c);
  c.meta.parameters.reset();
  write_configuration<3>(MPI_COMM_WORLD, without, c);

  const FileMeta meta = read_file_meta(MPI_COMM_SELF, with);
  ASSERT_TRUE(meta.parameters);
  EXPECT_TRUE(*meta.parameters == p);
  EXPECT_EQ(std::bit_cast<std::uint64_t>(meta.parameters->contact_law.k_n),
            std::bit_cast<std::uint64_t>(p.contact_law.k_n));
  EXPECT_TRUE(read_configuration<3>(MPI_COMM_WORLD, with).meta.parameters == p);
  const FileMeta none = read_file_meta(MPI_COMM_SELF, unset);
  ASSERT_TRUE(none.parameters);
  EXPECT_FALSE(none.parameters->stress_target.set());
  EXPECT_TRUE(none.parameters->stress_target == StressTarget{});
  EXPECT_FALSE(read_file_meta(MPI_COMM_SELF, without).parameters);
  MPI_Barrier(MPI_COMM_WORLD);
  if (rank == 0)
    for (const auto& f : {with, without, unset})
      std::filesystem::remove(f);
}

// Checkpoints of run_state format 1 (before /parameters) kept the stages' changes in the run
// state: they are restored over the deck's [material]; format 2 leaves them to /parameters.
TEST(CheckpointState, FormatOneRunStateRestoresOverTheDeck) {
  const Deck deck = parse_deck(kDeck, "a.toml");
  const std::string common = R"("stage_index": 2, "mid_stage": false, "ranks": 1, "grid": [1, 1, 1],
      "completed": [], "frames": [], "wall_seconds": 1.5)";
  const RunState old = parse_run_state(
      "{\"format\": 1, " + common + R"(, "friction": ")" + exact(0.5).get<std::string>() +
          R"(", "damping": ")" + exact(0.9).get<std::string>() + R"(", "stress": [")" +
          exact(1e4).get<std::string>() + "\", \"" + exact(1e4).get<std::string>() + "\", \"" +
          exact(1e4).get<std::string>() + R"("], "fixed": [false, false, false], "pressure": ")" +
          exact(1e4).get<std::string>() + "\"}",
      "old.h5");
  ASSERT_TRUE(old.legacy);
  const StateParameters p = legacy_parameters(old, deck);
  EXPECT_EQ(p.contact_law.friction, 0.5);
  EXPECT_EQ(p.contact_law.damping_ratio, 0.9);
  EXPECT_EQ(p.contact_law.young_modulus, 2.88e8); // the deck's
  EXPECT_EQ(p.stress_target.stage, 1);            // the compress stage before stage 2
  EXPECT_EQ(p.stress_target.stress, std::vector<double>(3, 1e4));
  EXPECT_EQ(p.stress_target.pressure, 1e4);
  EXPECT_FALSE(parse_run_state("{\"format\": 2, " + common + "}", "new.h5").legacy);
  EXPECT_THROW(parse_run_state("{\"format\": 3, " + common + "}", "new.h5"), InputError);
}

// Cut planes moved by load balancing travel as exact bit patterns; planes that do not fit the
// grid (count, order, ends) are a damaged checkpoint, refused with the file's name.
TEST(CheckpointState, CutPlanesRoundTripAndMustFitTheGrid) {
  const auto state = [](const std::string& cuts) {
    return R"({"format": 2, "stage_index": 1, "mid_stage": true, "ranks": 2, "grid": [2, 1, 1],
      "completed": [], "frames": [], "wall_seconds": 1.5, "cuts": )" +
           cuts + "}";
  };
  const auto x = [](double v) { return "\"" + exact(v).get<std::string>() + "\""; };
  const double c = 0.1 + 0.2; // not a short decimal: only an exact pattern keeps its bits
  const std::string one = "[" + x(0) + ", " + x(1) + "]";
  const RunState s = parse_run_state(
      state("[[" + x(0) + ", " + x(c) + ", " + x(1) + "], " + one + ", " + one + "]"), "cp.h5");
  ASSERT_EQ(s.cuts.size(), 3u);
  EXPECT_EQ(s.cuts[0], (std::vector<double>{0.0, c, 1.0}));
  EXPECT_EQ(s.cuts[2], (std::vector<double>{0.0, 1.0}));
  for (const std::string& bad :
       {"[[" + x(0) + ", " + x(1) + "], " + one + ", " + one + "]",
        "[[" + x(0) + ", " + x(0.7) + ", " + x(0.7) + "], " + one + ", " + one + "]",
        "[[" + x(0.1) + ", " + x(0.5) + ", " + x(1) + "], " + one + ", " + one + "]",
        "[[" + x(0) + ", " + x(0.5) + ", " + x(1) + "], " + one + "]"}) {
    try {
      parse_run_state(state(bad), "dir/cp.h5");
      ADD_FAILURE() << "accepted cuts " << bad;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("dir/cp.h5: /run_state's cut planes do not fit"),
                std::string::npos)
          << e.what();
    }
  }
}

} // namespace
} // namespace granpack
