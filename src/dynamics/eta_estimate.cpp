#include "granpack/dynamics/eta_estimate.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace granpack {

double EtaEstimate::worst_ratio(const EquilibriumMeasure& m) const {
  const double moment = tol_.checks_moment() ? m.moment / tol_.moment : 0.0;
  return std::max({m.force / tol_.force, m.stress / tol_.stress, m.kinetic / tol_.kinetic, moment});
}

std::optional<double> EtaEstimate::update_steps(const EquilibriumMeasure& m, std::int64_t step) {
  const double r = worst_ratio(m);
  if (!(r > 0) || !std::isfinite(r))
    return std::nullopt;
  const double lr = std::log(r);
  if (!first_step_)
    first_step_ = step;
  if (prev_log_ratio_ && step > prev_step_) {
    const double rate = (lr - *prev_log_ratio_) / double(step - prev_step_);
    // Smoothing: the criteria fluctuate from one line to the next.
    rate_ = rate_ ? 0.5 * (*rate_ + rate) : rate;
  }
  prev_log_ratio_ = lr;
  prev_step_ = step;
  if (r <= 1)
    return 0.0;
  if (!rate_ || *rate_ >= 0)
    return std::nullopt;
  const double steps = lr / -*rate_;
  const double history = double(std::max<std::int64_t>(step - *first_step_, 1));
  if (steps > kMaxExtrapolation * history)
    return std::nullopt;
  return steps;
}

std::string EtaEstimate::update(const EquilibriumMeasure& m, std::int64_t step, double steps_per_s,
                                std::int64_t last_step) {
  std::optional<double> steps = update_steps(m, step);
  if (last_step >= 0) {
    const double bound = double(std::max<std::int64_t>(last_step - step, 0));
    steps = steps ? std::min(*steps, bound) : bound;
  }
  if (!steps || !(steps_per_s > 0))
    return "  ETA -";
  return "  ETA " + human_duration(*steps / steps_per_s);
}

std::string human_duration(double seconds) {
  char buf[32];
  if (seconds < 90)
    std::snprintf(buf, sizeof buf, "%.0f s", seconds);
  else if (seconds < 5400)
    std::snprintf(buf, sizeof buf, "%.0f min", seconds / 60);
  else if (seconds < 172800)
    std::snprintf(buf, sizeof buf, "%.1f h", seconds / 3600);
  else
    std::snprintf(buf, sizeof buf, "%.1f d", seconds / 86400);
  return buf;
}

} // namespace granpack
