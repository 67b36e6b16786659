// Aerodynamic power for the inertia regression: the recording's column or the model on a centred wind
// average.
#include "aero_power_input.hpp"

#include <cmath>

namespace windfdi {

double model_aero_power(const AeroModel& aero, double wind, const FrameSample& s,
                        const PowerModelLimits& limits) {
  // Blade by blade: with individual pitch the blades' Cp differ and Cp is far from linear in pitch.
  if (!std::isfinite(wind) || wind < 0.0 || wind > limits.wind_max || !std::isfinite(s.rotor_speed) ||
      s.rotor_speed < 0.0 || s.rotor_speed > limits.rotor_speed_max)
    return kNaN;
  double p = 0.0;
  for (double pitch : s.pitch) {
    if (!std::isfinite(pitch) || pitch < limits.pitch_min || pitch > limits.pitch_max) return kNaN;
    p += aero.aero_power(wind, s.rotor_speed, pitch) / 3.0;
  }
  return p;
}

AeroPowerInput::AeroPowerInput(const AeroModel& aero, double wind_window, double sample_time,
                               PowerModelLimits limits)
    : aero_(aero),
      limits_(limits),
      half_(static_cast<std::size_t>(std::lround(0.5 * std::max(0.0, wind_window) / sample_time))),
      ring_(2 * half_ + 1) {}

bool AeroPowerInput::usable_wind(double v) const {
  return std::isfinite(v) && v >= 0.0 && v <= limits_.wind_max;
}

bool AeroPowerInput::push(const FrameSample& s, bool gap, FrameSample& out, bool& out_gap, double& power) {
  Entry& newest = at(size_++);
  newest = Entry{s, gap};
  for (int i = 0; i < kBlades; ++i)
    if (absent_ & (kValidPitch1 << i)) {
      newest.sample.pitch[static_cast<std::size_t>(i)] = absent_pitch_;
      newest.sample.valid_mask |= kValidPitch1 << i;
    }
  if (usable_wind(s.wind_hub)) wind_sum_ += s.wind_hub, ++wind_count_;
  if (std::isfinite(s.rotor_speed)) speed_sum_ += s.rotor_speed, ++speed_count_;
  // The next sample out is the one half a window behind the newest (at the start, with fewer before it).
  if (size_ - 1 - next_ < half_) return false;
  const Entry& centre = at(next_);
  out = centre.sample;
  out_gap = centre.gap;
  if (speed_average_ && std::isfinite(out.rotor_speed))
    out.rotor_speed = speed_sum_ / static_cast<double>(speed_count_);
  if (std::isfinite(out.aero_power)) {
    power = out.aero_power;  // the recording's column (replay contract)
  } else {
    power = usable_wind(out.wind_hub)
                ? model_aero_power(aero_, wind_sum_ / static_cast<double>(wind_count_), out, limits_)
                : kNaN;
  }
  if (++next_ > half_) {
    const FrameSample& oldest = at(0).sample;
    if (usable_wind(oldest.wind_hub)) wind_sum_ -= oldest.wind_hub, --wind_count_;
    if (std::isfinite(oldest.rotor_speed)) speed_sum_ -= oldest.rotor_speed, --speed_count_;
    head_ = (head_ + 1) % ring_.size();
    --size_;
    --next_;
  }
  return true;
}

}  // namespace windfdi
