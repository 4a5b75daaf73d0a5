#pragma once
// Running `granpack stiffness` inside an MPI test: a deck into a scratch directory, then the
// subcommand on its final packing, with the JSON report parsed (tests/mpi/stiffness.cpp,
// tests/mpi/elastic_tensor.cpp).
#include <gtest/gtest.h>
#include <mpi.h>

#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>

#include "few_ranks.h"
#include "granpack/app/run_deck.h"
#include "granpack/app/stiffness.h"
#include "mpi_world.h"
#include "test_paths.h"

namespace granpack::test {

inline nlohmann::json run_stiffness(const std::filesystem::path& file, double threshold = 1e-4,
                                    StiffnessSolver solver = StiffnessSolver::kAuto) {
  StiffnessOptions o;
  o.file = file;
  o.threshold = threshold;
  o.solver = solver;
  // An exception must not leave the capture open: the next test's capture would abort the
  // whole executable, and the exception's message would be lost.
  testing::internal::CaptureStdout();
  std::string text;
  try {
    text = stiffness_file(MPI_COMM_WORLD, o);
  } catch (...) {
    std::fputs(testing::internal::GetCapturedStdout().c_str(), stdout);
    throw;
  }
  testing::internal::GetCapturedStdout();
  return nlohmann::json::parse(text);
}

/// Runs a deck (text) into a scratch directory; returns final.h5.
inline std::filesystem::path run_text_deck(const std::string& tag, const std::string& text) {
  const auto dir = scratch_dir(tag + "_np" + std::to_string(world_size()));
  if (world_rank() == 0)
    std::ofstream(dir / "deck.toml") << text;
  MPI_Barrier(MPI_COMM_WORLD);
  RunOptions opt;
  opt.deck = dir / "deck.toml";
  opt.output_dir = dir / "out";
  opt.quiet = true;
  EXPECT_EQ(run_deck_on_few_ranks(opt), 0);
  return dir / "out" / "final.h5";
}

/// Runs jobs/decks/ci/NAME.toml into a scratch directory (tag + rank count); returns final.h5.
inline std::filesystem::path run_ci_deck_file(const std::string& name, const std::string& tag) {
  RunOptions opt;
  opt.deck = source_dir() / "jobs/decks/ci" / (name + ".toml");
  opt.output_dir = scratch_dir(tag + "_np" + std::to_string(world_size()));
  opt.quiet = true;
  EXPECT_EQ(run_deck_on_few_ranks(opt), 0);
  return opt.output_dir / "final.h5";
}

} // namespace granpack::test
