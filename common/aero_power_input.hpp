// Aerodynamic power from the turbine model on a centred anemometer average (or the recording's column), read
// by ice_detect's inertia regression and drive_train's energy balance.
#pragma once

#include <cstddef>
#include <vector>

#include "frame_sample.hpp"
#include "turbine_params.hpp"

namespace windfdi {

/// Plausible measurements for the power model: beyond them a sample has no power (NaN), not a wild one.
struct PowerModelLimits {
  double wind_max = 60.0;        ///< m/s
  double rotor_speed_max = 5.0;  ///< rad/s
  double pitch_min = -5.0;       ///< deg
  double pitch_max = 95.0;       ///< deg
};

/// Aerodynamic power of one turbine's samples: the recording's `aero_power` when present, else the turbine
/// model on the anemometer, rotor speed and each blade's pitch. The anemometer's noise (0.5 m/s a sample)
/// through the cubic, Cp-shaped model leaves a power bias that moves with the operating point, which the
/// inertia regression cannot tell from the rotor's own transients; a causal low-pass would trade it for a
/// lag that is worse still. So the wind is averaged over a window centred on each sample: samples leave
/// half a window (a fraction of a second) late, with their power.
class AeroPowerInput {
 public:
  /// `wind_window` (s, 0: no averaging) at the sample time `sample_time` (s).
  AeroPowerInput(const AeroModel& aero, double wind_window, double sample_time, PowerModelLimits limits = {});
  /// Takes a sample (`gap`: samples were lost before it). Returns true when a delayed sample is out, in
  /// `out` and `out_gap`, with its aerodynamic power in `power` (NaN when an input is missing or out of
  /// range). A gap does not break the average: the wind a second apart is still the same gust.
  bool push(const FrameSample& s, bool gap, FrameSample& out, bool& out_gap, double& power);
  /// `absent`: valid bits of channels the turbine's data does not carry (InputContext::absent). An absent
  /// blade pitch is taken as `absent_pitch` (deg): a fixed-pitch or stall-regulated rotor's blade angle.
  void set_absent(uint32_t absent, double absent_pitch) {
    absent_ = absent;
    absent_pitch_ = absent_pitch;
  }
  /// On: the sample out carries the window's mean rotor speed (its finite values), centred as the wind's,
  /// and its power is the model's at it. For a speed sensor too noisy to take sample by sample (the rotor's,
  /// where a generator's is the usual source).
  void set_speed_average(bool on) { speed_average_ = on; }

 private:
  bool usable_wind(double v) const;
  struct Entry {
    FrameSample sample;
    bool gap = false;
  };
  const AeroModel& aero_;
  PowerModelLimits limits_;
  Entry& at(std::size_t i) { return ring_[(head_ + i) % ring_.size()]; }
  std::size_t half_;  // samples each side of the centre
  // The window: half_ samples before the next one out, it, and up to half_ after, at most 2 half_ + 1 in a
  // ring from head_ (a deque of these 200-byte entries allocated a block every other sample).
  std::vector<Entry> ring_;
  std::size_t head_ = 0, size_ = 0;
  std::size_t next_ = 0;   // index in the window of the next sample out
  double wind_sum_ = 0.0;  // over the window's finite anemometer values
  std::size_t wind_count_ = 0;
  double speed_sum_ = 0.0;  // over the window's finite rotor speeds
  std::size_t speed_count_ = 0;
  bool speed_average_ = false;
  uint32_t absent_ = 0;
  double absent_pitch_ = 0.0;
};

/// The model's aerodynamic power (W) at hub wind `wind` (m/s), blade by blade; NaN for a missing or out of
/// range input.
double model_aero_power(const AeroModel& aero, double wind, const FrameSample& s,
                        const PowerModelLimits& limits = {});

}  // namespace windfdi
