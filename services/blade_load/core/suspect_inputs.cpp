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

double SuspectInputs::response_departure(int b, const FrameSample& s, double a) {
  const double pitch = s.pitch[b], ref = s.pitch_ref[b];
  if (!std::isfinite(pitch) || !std::isfinite(ref) || !(s.valid_mask & (kValidPitch1 << b))) {
    response_started_[b] = false;
    return 0.0;
  }
  if (!response_started_[b]) {
    // From the reading: a bias there from the start shows once the response has settled on the reference
    // (about 0.5 s).
    response_[b] = PitchActuator{pitch, 0.0};
    response_departure_[b] = 0.0;
    response_started_[b] = true;
  }
  response_departure_[b] += a * (pitch - response_[b].angle - response_departure_[b]);
  // Sub-steps of at most 2 ms: the plant integrates at 500 Hz, and omega_n h stays below 0.03.
  const int steps = std::max(1, static_cast<int>(std::ceil(dt_ / 0.002)));
  for (int k = 0; k < steps; ++k)
    response_[b].step(ref, dt_ / steps, c_.pitch_omega_n, c_.pitch_zeta, c_.pitch_rate_limit, c_.pitch_min,
                      c_.pitch_max);
  return response_departure_[b];
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
  // The reading against what the healthy actuator makes of its reference: the response is restarted after a
  // hole (the references in it are unknown).
  if (last_t_ >= 0.0 && s.t - last_t_ > 1.5 * dt_) response_started_.fill(false);
  last_t_ = s.t;
  if (c_.pitch_response_mismatch > 0.0)
    for (int b = 0; b < 3; ++b)
      suspect |= std::fabs(response_departure(b, s, a)) > c_.pitch_response_mismatch;
  // Then what the other services and the arbiter say. A fault on one speed sensor is held only through its
  // transient (context_hold after it is raised and after the arbiter's switch to the corrected speed): the
  // model predicts from the measured rotor speed (or its twin) and pitch, whatever speed the controller ran
  // on, and holding for the whole fault hid 3 of 29 intermittent blade-moment faults in the suite (seed 15).
  for (int b = 0; b < 3; ++b)
    suspect |= c.pitch_sensor_suspect[b] || (c_.actuator_report_holds && c.pitch_actuator_suspect[b]);
  suspect = suspect || (c.rotor_speed_suspect && !twin_usable(s)) || hold_.in_transient(s.t);
  if (suspect) ++suspect_samples_;
  return suspect;
}

}  // namespace windfdi::blade_load
