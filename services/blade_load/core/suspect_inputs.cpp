// Suspect inputs of the LIDAR load model: redundancy first, then the other services and the arbiter.
#include "suspect_inputs.hpp"

#include <algorithm>
#include <cmath>

namespace windfdi::blade_load {

bool SuspectInputs::twin_usable(const FrameSample& s) const {
  return !hold_.context().generator_speed_suspect && c_.gear_ratio > 0.0 &&
         std::isfinite(s.generator_speed) && (s.valid_mask & kValidGeneratorSpeed) &&
         s.generator_speed >= 0.0;
}

bool SuspectInputs::speed_twin(const FrameSample& s, FrameSample& twin) const {
  if (!hold_.context().rotor_speed_suspect || !twin_usable(s)) return false;
  twin = s;
  twin.rotor_speed = s.generator_speed / c_.gear_ratio;  // finite: twin_usable checked both
  twin.valid_mask |= kValidRotorSpeed;
  return true;
}

bool SuspectInputs::update(const FrameSample& s) {
  // Redundancy first (no other service needed): the two speed sensors, and each pitch reading against its
  // reference, low-passed over 0.5 s (sensor noise 0.025 rad/s, 0.2 deg).
  const double a = dt_ / (0.5 + dt_);
  bool suspect = false;
  const InputContext& c = hold_.context();
  // A fault another service has placed on one speed sensor explains a mismatch of the two, and leaves lambda
  // known: from the rotor speed, or from its twin (speed_twin) when the rotor speed is the faulty one.
  const bool one_placed = c.generator_speed_suspect != c.rotor_speed_suspect;
  if (c_.speed_mismatch > 0.0 && c_.gear_ratio > 0.0 && std::isfinite(s.generator_speed) &&
      (s.valid_mask & kValidGeneratorSpeed)) {
    const double m =
        std::fabs(s.rotor_speed - s.generator_speed / c_.gear_ratio) / std::max(s.rotor_speed, 0.1);
    speed_mismatch_lp_ += a * (std::min(m, 1.0) - speed_mismatch_lp_);
    suspect |= speed_mismatch_lp_ > c_.speed_mismatch && !one_placed;
  }
  for (int b = 0; b < 3; ++b) {
    if (c_.pitch_mismatch <= 0.0 || !std::isfinite(s.pitch[b]) || !std::isfinite(s.pitch_ref[b])) continue;
    pitch_mismatch_lp_[b] += a * (std::fabs(s.pitch[b] - s.pitch_ref[b]) - pitch_mismatch_lp_[b]);
    suspect |= pitch_mismatch_lp_[b] > c_.pitch_mismatch;
  }
  // Then what the other services and the arbiter say. A fault on one speed sensor is held only through its
  // transient (context_hold after it is raised and after the arbiter's switch to the corrected speed): the
  // model predicts from the measured rotor speed (or its twin) and pitch, whatever speed the controller ran
  // on, and holding for the whole fault hid 3 of 29 intermittent blade-moment faults in the suite (seed 15).
  for (int b = 0; b < 3; ++b) suspect |= c.pitch_sensor_suspect[b] || c.pitch_actuator_suspect[b];
  suspect = suspect || (c.rotor_speed_suspect && !twin_usable(s)) || hold_.in_transient(s.t);
  if (suspect) ++suspect_samples_;
  return suspect;
}

}  // namespace windfdi::blade_load
