// EtaEstimate: an exponentially decaying criterion is extrapolated to the right step.
#include <gtest/gtest.h>

#include <cmath>

#include "granpack/dynamics/eta_estimate.h"

namespace granpack {
namespace {

EquilibriumMeasure measure_with_force(double f) {
  EquilibriumMeasure m;
  m.force = f;
  return m;
}

TEST(EtaEstimate, ExtrapolatesAnExponentialDecay) {
  EquilibriumTolerances tol; // force 1e-4
  EtaEstimate eta(tol);
  // r = 1e3 * exp(-k s): reaches 1 (force = 1e-4) at s = ln(1e3)/k.
  const double k = 1e-4;
  EXPECT_FALSE(eta.update_steps(measure_with_force(1e-1), 0).has_value()); // one point: no rate
  const auto steps = eta.update_steps(measure_with_force(1e-1 * std::exp(-k * 1000)), 1000);
  ASSERT_TRUE(steps.has_value());
  EXPECT_NEAR(*steps, std::log(1e3) / k - 1000, 1e-6 * std::log(1e3) / k);
}

TEST(EtaEstimate, NoEstimateWhileGrowingAndZeroOnceMet) {
  EtaEstimate eta(EquilibriumTolerances{});
  eta.update_steps(measure_with_force(1e-2), 0);
  EXPECT_FALSE(eta.update_steps(measure_with_force(2e-2), 100).has_value());
  EXPECT_EQ(eta.update_steps(measure_with_force(1e-5), 200).value_or(-1), 0.0);
}

TEST(EtaEstimate, NoFarExtrapolationFromAShortHistory) {
  // A compression's |dP|/P ~ 1 drifting by 1e-6 per 1000 steps: the decay would "reach" the
  // tolerance after ~1e10 steps, 1e7 times the history; no estimate rather than "ETA 2147 d".
  EquilibriumTolerances tol; // stress 1e-4
  EtaEstimate eta(tol);
  EquilibriumMeasure m;
  m.stress = 1.0;
  eta.update_steps(m, 0);
  m.stress = 1.0 - 1e-6;
  EXPECT_FALSE(eta.update_steps(m, 1000).has_value());
  // The same decay observed for long enough is extrapolated again: ln(1e4)/1e-9 ~ 9.2e9
  // steps is within 100 x a history of 1e8 steps.
  EtaEstimate late(tol);
  m.stress = 1.0;
  late.update_steps(m, 0);
  m.stress = std::exp(-1e-9 * 1e8);
  const auto steps = late.update_steps(m, 100000000);
  ASSERT_TRUE(steps.has_value());
  EXPECT_NEAR(*steps, std::log(m.stress / 1e-4) / 1e-9, 1e-6 * *steps);
}

TEST(EtaEstimate, TextUsesTheMaxStepsBound) {
  EtaEstimate eta(EquilibriumTolerances{});
  // Not decreasing: only the bound, 1000 steps at 100 steps/s.
  EXPECT_EQ(eta.update(measure_with_force(1e-2), 0, 100.0, 1000), "  ETA 10 s");
  EXPECT_EQ(eta.update(measure_with_force(1e-2), 500, 100.0, -1), "  ETA -");
}

TEST(HumanDuration, Units) {
  EXPECT_EQ(human_duration(45), "45 s");
  EXPECT_EQ(human_duration(600), "10 min");
  EXPECT_EQ(human_duration(3 * 3600), "3.0 h");
  EXPECT_EQ(human_duration(3 * 86400), "3.0 d");
}

} // namespace
} // namespace granpack
