// `granpack analyze` on a packing written by the engine (on at most 2 ranks: few_ranks.h):
// known values on the FCC case, and the same results on 1 rank as on all ranks (counts
// exactly, reals within 1e-12).
#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "few_ranks.h"
#include "granpack/app/analyze.h"
#include "granpack/app/run_deck.h"
#include "test_paths.h"

using namespace granpack;

TEST(Analyze, FccPackingAndRankCountInvariance) {
  int size = 1, rank = 0;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  const auto out = test::scratch_dir("analyze_fcc_np" + std::to_string(size));
  RunOptions opt;
  opt.deck = test::source_dir() / "jobs/decks/ci/fcc_hertz.toml";
  opt.output_dir = out;
  opt.quiet = true;
  ASSERT_EQ(test::run_deck_on_few_ranks(opt), 0);

  AnalyzeOptions a;
  a.file = out / "final.h5";
  testing::internal::CaptureStdout();
  const auto all = nlohmann::json::parse(analyze_file(MPI_COMM_WORLD, a));
  testing::internal::GetCapturedStdout();
  EXPECT_EQ(all["n"], 256);
  EXPECT_EQ(all["backbone_contacts"], 1536);
  EXPECT_EQ(all["rattlers"], 0);
  EXPECT_DOUBLE_EQ(all["z"].get<double>(), 12.0);
  EXPECT_NEAR(all["Z_2"].get<double>(), 1.0, 1e-12); // every contact carries the same force
  EXPECT_NEAR(all["Z_5_3"].get<double>(), 1.0, 1e-12);
  // eq. (22) neglects the deflection: its relative error is of order h/a = 2.67e-5 here.
  EXPECT_GT(all["eq22_relative_error"].get<double>(), 1e-5);
  EXPECT_LT(all["eq22_relative_error"].get<double>(), 1e-4);
  // 3 a requested; the cubic cell (4 FCC cells, 5.66 a) allows 2.83 a; a grid with 3 or more
  // sub-domains along an axis (3 ranks: 3x1x1) cuts it into slabs of 1.89 a or less.
  int dims[3] = {0, 0, 0};
  MPI_Dims_create(size, 3, dims);
  EXPECT_EQ(all["g_r_range_limited_by"], dims[0] >= 3 ? "sub-domain width" : "half the cell");

  if (rank != 0)
    return;
  testing::internal::CaptureStdout();
  const auto one = nlohmann::json::parse(analyze_file(MPI_COMM_SELF, a));
  testing::internal::GetCapturedStdout();
  for (auto& [key, v] : all.items()) {
    // X1, M1, M2 split contacts at N = <N>: here every contact carries the same force, so the
    // split (and whether M1 is defined) depends on the last bit of <N>.
    if (key == "X1" || key == "M1" || key == "M2")
      continue;
    // The g(r) range is clipped by the sub-domain width on 3 ranks or more (this cell is
    // 5.66 a wide, the requested range 3 a); the output says so. g(r) itself is not compared.
    if (key == "g_r_range" && all["g_r_range_limited_by"] == "sub-domain width") {
      EXPECT_LT(v.get<double>(), one[key].get<double>());
      continue;
    }
    if (v.is_number_integer()) {
      EXPECT_EQ(v, one[key]) << key;
    } else if (v.is_number_float()) {
      // A relative error (a dimensionless difference from 1) is compared in absolute terms.
      const double scale = key == "eq22_relative_error" ? 1.0 : std::abs(v.get<double>());
      EXPECT_NEAR(v.get<double>(), one[key].get<double>(), 1e-12 * scale) << key;
    }
  }
}
