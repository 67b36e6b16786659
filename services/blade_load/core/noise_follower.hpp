// The present noise level of each residual channel, read from the three pairs of blades, and the factor >= 1
// the channel's t-values are divided by.
#pragma once

#include <array>

#include "residual_channels.hpp"

namespace windfdi::blade_load {

/// A residual's spread is not stationary: it follows how far the beams' wind is from the rotor's and how
/// differently the three blades sample the turbulence (low wind, where the mean load is small, TI 0.155:
/// one-revolution values three times the spread learned at start-up for minutes, and four false reports in
/// 2000 s). The level is the mean square of each pair of blades' difference over `revolutions`.
class NoiseFollower {
 public:
  /// `revolutions`: the averaging length (0: off, the scale stays 1).
  explicit NoiseFollower(double revolutions) : revolutions_(revolutions) {}
  /// One revolution: each blade's deviation from its healthy mean (NaN: none) and the unit its test divides
  /// by. A pair with a `held` blade keeps its level.
  void follow(const BladeChannels& deviation, const BladeChannels& unit,
              const std::array<bool, 3>& held = {});
  /// The factor a channel's t-values are divided by now (>= 1).
  double scale(int channel) const { return level_[channel].scale; }

 private:
  struct Level {
    std::array<double, 3> pair_var{-1.0, -1.0,
                                   -1.0};  ///< mean square of each pair's difference; < 0: not started
    double scale = 1.0;
  };
  double revolutions_;
  std::array<Level, kChannels> level_{};
};

}  // namespace windfdi::blade_load
