// The parts of a checkpoint beyond the grains: exact doubles, /run_state parsing, and the
// deck comparison that refuses unsafe restarts.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <limits>

#include "granpack/core/error.h"
#include "granpack/prep/checkpoint.h"

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
  s.mid_stage = true;  // inside the compress stage
  std::string text = kDeck;
  EXPECT_EQ(message_of(a, parse_deck(text + "[output]\nlog_every = 7\n", "b.toml"), s, false), "");
  const std::string friction = message_of(a, parse_deck(std::string(kDeck).replace(text.find("friction = 0.3"), 14, "friction = 0.4"), "b.toml"), s, false);
  EXPECT_NE(friction.find("[material]"), std::string::npos) << friction;
  // The stage in progress may not change, even with the flag.
  const std::string p = std::string(kDeck).replace(text.find("pressure = 1.0e4"), 16, "pressure = 2.0e4");
  const std::string in_progress = message_of(a, parse_deck(p, "b.toml"), s, true);
  EXPECT_NE(in_progress.find("stage[1]"), std::string::npos) << in_progress;
  // A later stage may, with the flag only.
  const std::string w = std::string(kDeck).replace(text.find("a.h5"), 4, "b.h5");
  EXPECT_NE(message_of(a, parse_deck(w, "b.toml"), s, false).find("allow-deck-change"), std::string::npos);
  EXPECT_EQ(message_of(a, parse_deck(w, "b.toml"), s, true), "");
}

}  // namespace
}  // namespace granpack
