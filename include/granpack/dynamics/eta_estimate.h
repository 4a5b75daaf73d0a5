#pragma once
// Estimated time to the [AR] equilibrium criteria, for progress lines of long stages.
// While a packing settles, the worst criterion ratio r = max(measured / tolerance) decays
// roughly exponentially; its logarithmic rate between two progress lines (smoothed) is
// extrapolated to the step where r reaches 1. A stage with max_steps also has an upper bound.
// An extrapolation more than kMaxExtrapolation times longer than the history it rests on is
// not given: while a gas is compressed, |dP|/P stays near 1 and its slow drift would promise
// "ETA 2147 d".
#include <cstdint>
#include <optional>
#include <string>

#include "granpack/dynamics/equilibrium.h"

namespace granpack {

class EtaEstimate {
public:
  explicit EtaEstimate(const EquilibriumTolerances& t) : tol_(t) {}

  /// Worst ratio of a measure to its tolerance (< 1: every criterion holds).
  double worst_ratio(const EquilibriumMeasure& m) const;
  /// Longest extrapolation given, in units of the steps observed so far.
  static constexpr double kMaxExtrapolation = 100.0;

  /// Feeds the measure at `step`; returns the estimated steps still needed, if any.
  std::optional<double> update_steps(const EquilibriumMeasure& m, std::int64_t step);
  /// update_steps, as text for a progress line: "  ETA 12 min" / "  ETA -" (with the
  /// max_steps bound when last_step >= 0), at `steps_per_s`.
  std::string update(const EquilibriumMeasure& m, std::int64_t step, double steps_per_s,
                     std::int64_t last_step);

private:
  EquilibriumTolerances tol_;
  std::optional<double> prev_log_ratio_;
  std::int64_t prev_step_ = 0;
  std::optional<std::int64_t> first_step_;
  std::optional<double> rate_; ///< smoothed d ln(r) / d step (negative while converging)
};

/// "45 s", "12 min", "3.5 h", "2.1 d".
std::string human_duration(double seconds);

} // namespace granpack
