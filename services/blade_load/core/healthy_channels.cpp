// Learning and slow adaptation of the blades' healthy residual statistics.
#include "healthy_channels.hpp"

#include <algorithm>
#include <cmath>

namespace windfdi::blade_load {

std::array<bool, kChannels> HealthyChannels::learn(double t, const BladeChannels& x) {
  // Learn each channel's healthy distribution in the start-up phase, then freeze it.
  std::array<bool, kChannels> frozen{};
  for (int c = 0; c < kChannels; ++c) {
    if (stats_[0][c].learned) continue;
    if (!(std::isfinite(x[0][c]) && std::isfinite(x[1][c]) && std::isfinite(x[2][c]))) continue;
    if (first_value_t_[c] < 0) first_value_t_[c] = t;
    for (int b = 0; b < 3; ++b) learners_[b][c].add(x[b][c]);
    if (t - first_value_t_[c] >= c_.learn_time && learners_[0][c].size() >= c_.min_learn_revolutions) {
      for (int b = 0; b < 3; ++b) {
        stats_[b][c] = learners_[b][c].freeze();
        learners_[b][c].clear();
      }
      frozen[c] = true;
    }
  }
  return frozen;
}

void HealthyChannels::adapt(const BladeChannels& x, double revolution_time,
                            const std::array<bool, 3>& exceeding) {
  if (!(c_.healthy_adapt_time > 0 && revolution_time > 0)) return;
  const double w = std::min(1.0, revolution_time / c_.healthy_adapt_time);
  for (int b = 0; b < 3; ++b)
    for (int c = 0; c < kChannels; ++c) {
      HealthyStats& h = stats_[b][c];
      const double v = x[b][c];
      if (!h.learned || !std::isfinite(v) || exceeding[b]) continue;
      // Winsorised: one gust transient must not inflate (or drag) the healthy statistics.
      const double lim = c_.robust_clip * h.sd();
      const double d = std::clamp(v - h.mean, -lim, lim);
      h.mean += w * d;
      h.var += w * (d * d - h.var);
    }
}

}  // namespace windfdi::blade_load
