// The sampled CPU timing of the force phase (engine/step_timers.h): which evaluations are
// sampled, and how the CPU time of all is estimated from them. No timing is asserted, only
// which counters a timed evaluation moves.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "granpack/engine/step_timers.h"

namespace granpack {
namespace {

TEST(ForcePhaseTimer, SamplesTheFirstEvaluationAndEverySixteenthAfterIt) {
  StepTimers t;
  std::vector<std::int64_t> sampled;
  for (std::int64_t e = 0; e < 3 * kCpuSampleEvery + 1; ++e) {
    const double before = t.forces_sampled;
    {
      ForcePhaseTimer timer(t);
      // Some work, so that the interval's wall time is positive on a nanosecond clock.
      volatile double x = 0;
      for (int k = 0; k < 1000; ++k)
        x = x + 1.0;
    }
    if (t.forces_sampled > before) // a sampled evaluation adds its wall time
      sampled.push_back(e);
  }
  EXPECT_EQ(t.force_evaluations, 3 * kCpuSampleEvery + 1);
  EXPECT_EQ(sampled, (std::vector<std::int64_t>{0, kCpuSampleEvery, 2 * kCpuSampleEvery,
                                                3 * kCpuSampleEvery}));
  EXPECT_LE(t.forces_sampled, t.forces);
}

TEST(StepTimers, EstimatesTheForceCpuTimeFromTheSample) {
  StepTimers t;
  EXPECT_EQ(t.forces_cpu_estimate(), 0.0); // nothing sampled yet
  t.forces = 10.0, t.forces_sampled = 2.0, t.forces_cpu_sampled = 1.5;
  EXPECT_DOUBLE_EQ(t.forces_cpu_estimate(), 7.5); // 10 s of wall at the sample's 0.75
  StepTimers u;
  u.forces = 6.0, u.forces_sampled = 2.0, u.forces_cpu_sampled = 0.5, u.force_evaluations = 40;
  t += u;
  EXPECT_EQ(t.force_evaluations, 40);
  EXPECT_DOUBLE_EQ(t.forces_cpu_estimate(), 16.0 * (2.0 / 4.0));
}

} // namespace
} // namespace granpack
