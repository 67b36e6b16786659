// The turbine's own time (its samples' time) for the arbiter's timers, between the inputs that carry it.
#pragma once

#include <algorithm>

namespace windfdi::arbiter {

/// Confirm, settle and clear-hold timers count seconds of the turbine's time, not of the arbiter's wall
/// clock: a plant run at 10x real time must stop a turbine after the same 10 s of evidence. Inputs carry
/// sample time (fault reports on change, pitch estimates at 10 Hz); in between, the clock runs on at the
/// rate measured over the last observations. Never goes back.
class TurbineClock {
 public:
  /// An input stamped with turbine time `t` arrived at wall time `wall` (s).
  void observe(double t, double wall) {
    if (!have_) {
      have_ = true;
      anchor_t_ = t_ = t;
      anchor_wall_ = wall_ = wall;
      return;
    }
    if (t < t_) return;  // an older sample (another service's lag): the newest one sets the clock
    if (wall - anchor_wall_ >= kRateSpan) {
      rate_ = std::clamp((t - anchor_t_) / (wall - anchor_wall_), kMinRate, kMaxRate);
      anchor_t_ = t;
      anchor_wall_ = wall;
    }
    t_ = t;
    wall_ = wall;
  }
  /// Turbine time at wall time `wall` (0 before the first input: the arbiter then has nothing to time).
  double now(double wall) {
    if (!have_) return 0.0;
    last_ = std::max(last_, t_ + std::max(0.0, wall - wall_) * rate_);
    return last_;
  }
  double rate() const { return rate_; }

 private:
  static constexpr double kRateSpan = 2.0;  // s of wall time over which the rate is measured
  static constexpr double kMinRate = 0.05, kMaxRate = 1000.0;
  bool have_ = false;
  double t_ = 0.0, wall_ = 0.0, anchor_t_ = 0.0, anchor_wall_ = 0.0, rate_ = 1.0, last_ = -1e300;
};

}  // namespace windfdi::arbiter
