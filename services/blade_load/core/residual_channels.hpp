// The residual channels of each blade: the paper's delta_A from the gauge and LIDAR-model first harmonics
// (Stotsky 2014), with the other two blades as witnesses, and the sensors alone when the LIDAR is missing.
#pragma once

#include <array>
#include <cmath>

namespace windfdi::blade_load {

/// Residual channels per blade, each with its own healthy distribution.
/// kModel: (A_model - A_sensor) / mean load (the paper's delta_A). kWitness: the same residual minus the
/// other two blades' (a common LIDAR-model error cancels). kMean: the sensor/model mean-load ratio minus the
/// other blades' (an offset or drift). kRawWitness, kRawMean: the sensors alone against each other, when the
/// LIDAR is missing.
enum Channel {
  kModelChannel = 0,
  kWitnessChannel,
  kMeanChannel,
  kRawWitnessChannel,
  kRawMeanChannel,
  kChannels
};
/// One value per blade and residual channel.
using BladeChannels = std::array<std::array<double, kChannels>, 3>;
const char* channel_name(int c);
/// +1 when a value v of channel c says the gauge reads high (above the model or the other gauges), -1 low:
/// kModel is model minus sensor, every other channel sensor minus its reference.
inline int reading_direction(int c, double v) { return (c == kModelChannel ? -v : v) > 0 ? 1 : -1; }
/// The channels on mean loads (an offset or drift moves them; a constant added to a gauge leaves its first
/// harmonic alone).
inline bool mean_load_channel(int c) { return c == kMeanChannel || c == kRawMeanChannel; }
/// A witness shift shares `shift`: the same sign and at least `share` of its size (false when either is NaN).
inline bool shares_shift(double witness, double shift, double share) {
  return witness * shift > 0.0 && std::fabs(witness) >= share * std::fabs(shift);
}
/// Every value NaN (not available).
BladeChannels unavailable_channels();

/// Each blade's first harmonic and mean load over the last window, from its gauge and from the LIDAR load
/// model, as of the last solve (eqs 6-7).
struct BladeEstimates {
  std::array<bool, 3> sensor_valid{}, model_valid{};  ///< the window was filled and well conditioned
  std::array<double, 3> a_sensor{}, a_model{};        ///< |A_1| (N m)
  std::array<double, 3> mean_sensor{}, mean_model{};  ///< window mean (N m)
};

/// The rotor's mean blade load in the last window (N m): the median of the gauges' window means, which one
/// failed gauge cannot move beyond the other two; NaN when fewer than two gauges are valid.
double window_load(const BladeEstimates& e);
/// The channels of the three blades (NaN where a blade's window or the LIDAR gives none).
BladeChannels residual_channels(const BladeEstimates& e);
/// A blade's fault size behind channel c in N m (0 for c < 0): what its gauge reads beyond the model or the
/// other blades.
double residual_size(const BladeEstimates& e, int blade, int c);
/// That size as a share of what the other two blades read on the same quantity (first-harmonic amplitude or
/// mean load); NaN when they read nothing.
double residual_share(const BladeEstimates& e, int blade, int c);

}  // namespace windfdi::blade_load
