// Following each residual channel's present noise level on the pairs of blades.
#include "noise_follower.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace windfdi::blade_load {

void NoiseFollower::follow(const BladeChannels& deviation, const BladeChannels& unit,
                           const std::array<bool, 3>& held) {
  // The present level is the smallest of the three pairs of blades' mean square differences: a failed gauge
  // is one blade and moves both pairs it is in, never the third. A pair's difference is taken in the
  // residual's own units (each blade's deviation from its healthy mean) over the pair's mean unit (the
  // tests' denominators): a fault on blade 1 moves the cross-blade residuals of blades 2 and 3 by the same
  // -delta / 2, but their t-values by different amounts (their learned spreads and autocorrelations differ),
  // and read in t a 1 %/min drift inflated its own noise level 2.5-fold in 300 s (found once in two runs).
  // Each pair is followed on its own (the smallest of three followed levels, not the level of the smallest
  // per revolution): a 10-revolution window mean barely changes from one revolution to the next, so a
  // per-revolution choice kept switching to whichever pair the fault's slow effect on the loads had least
  // separated. The t-values are divided by that level only when it is above the healthy one, so calm weather
  // keeps the test's full power.
  constexpr double kPairVariance[kChannels] = {2.0, 3.0, 3.0, 3.0, 3.0};
  if (revolutions_ <= 0) return;
  for (int c = 0; c < kChannels; ++c) {
    if (c == kWitnessChannel) continue;  // it only confirms the LIDAR residual
    if (!(std::isfinite(deviation[0][c]) && std::isfinite(deviation[1][c]) && std::isfinite(deviation[2][c])))
      continue;
    Level& L = level_[c];
    double spread = std::numeric_limits<double>::infinity();
    for (int i = 0; i < 3; ++i) {
      const int j = (i + 1) % 3;
      const double u = std::sqrt(0.5 * (unit[i][c] * unit[i][c] + unit[j][c] * unit[j][c]));
      const double d = (deviation[i][c] - deviation[j][c]) / u;
      if (L.pair_var[i] < 0) L.pair_var[i] = kPairVariance[c];
      if (!held[i] && !held[j]) L.pair_var[i] += (d * d - L.pair_var[i]) / revolutions_;
      spread = std::min(spread, L.pair_var[i]);
    }
    L.scale = std::max(1.0, std::sqrt(spread / kPairVariance[c]));
  }
}

}  // namespace windfdi::blade_load
