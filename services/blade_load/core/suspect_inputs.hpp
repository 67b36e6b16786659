// Whether the inputs the LIDAR load model relies on (rotor speed for lambda, each blade's pitch for k_M) can
// be trusted: the redundant speed sensors, each pitch against its reference, and what the rest of the system
// reports (input_context.hpp).
#pragma once

#include <array>
#include <cstdint>

#include "frame_sample.hpp"
#include "input_context.hpp"
#include "pitch_actuator.hpp"

namespace windfdi::blade_load {

/// Inputs the load model relies on (rotor speed for lambda, each blade's pitch for k_M): while one is suspect
/// no window is tested or learned (the steep-surface gate's hold), and an episode in progress is held.
struct SuspectInputConfig {
  double gear_ratio = 0.0;       ///< N (turbine file): the generator speed / N is the rotor speed's twin
  double speed_mismatch = 0.05;  ///< relative |omega_r - omega_g / N| / omega_r (0.5 s low-pass) above which
                                 ///< the two speed sensors disagree: lambda is not known (0..1, 0: off)
  double pitch_mismatch = 3.0;  ///< deg, |pitch_i - pitch_ref_i| (0.5 s low-pass) above which blade i's pitch
                                ///< reading or its actuator is not what the model assumes (0: off; healthy
                                ///< lag 1 deg at 10 deg/s)
  /// deg: the pitch reading's departure (0.5 s low-pass, signed) from the response of the turbine's healthy
  /// actuator to the blade's reference above which the reading is suspect (0: off). The actuator follows its
  /// reference, not its reading: a biased pitch sensor (1.0-2.9 deg in the suite) misleads the model alone,
  /// which read it as the blade's gauge failing 1.2-2.4 s after the bias began, before sensor_bias reported
  /// it. Healthy departures stay below 0.11 deg (noise 0.2 deg, safe stops included); a pump-worn actuator's
  /// reach 0.49 deg.
  double pitch_response_mismatch = 0.5;
  // The healthy actuator (turbine file).
  double pitch_omega_n = 11.11;    ///< rad/s
  double pitch_zeta = 0.6;         ///< -
  double pitch_rate_limit = 10.0;  ///< deg/s
  double pitch_min = -2.0;         ///< deg
  double pitch_max = 90.0;         ///< deg
  /// A reported pitch actuator holds every test while it stays raised (false: through context_hold only; the
  /// blade's reading is true, and pitch_response_mismatch still holds while it departs from a healthy
  /// actuator's response). A report awaiting maintenance (or one that outlived its fault) hid a gauge's gain
  bool actuator_report_holds = false;
  double context_hold = 10.0;  ///< s held after another service raised or cleared a fault on an input the
                               ///< model uses (a speed or pitch sensor, an actuator), or the arbiter
                               ///< reconfigured the controller; held as long as a pitch sensor's fault
                               ///< stays raised (a fault on one speed sensor, or an actuator's unless
                               ///< actuator_report_holds: only this long; lambda comes from the other one)
};

class SuspectInputs {
 public:
  /// `dt`: the sample period (s).
  SuspectInputs(const SuspectInputConfig& c, double dt) : c_(c), dt_(dt), hold_(c.context_hold) {}
  /// One sample: true when an input of the load model is suspect now (counted).
  bool update(const FrameSample& s);
  /// The inputs' context (input_context.hpp) from sample time t on.
  void set_context(const InputContext& context, double t) { hold_.set(context, t); }
  /// While another service reports the rotor speed and not the generator speed: `s` with the rotor speed
  /// replaced by its redundant twin, the generator speed over the gear ratio (true; else false).
  bool speed_twin(const FrameSample& s, FrameSample& twin) const;
  /// Samples on which an input was suspect.
  uint64_t suspect_samples() const { return suspect_samples_; }
  /// Blade b's pitch reading less its healthy actuator's response to the reference (deg, 0.5 s low-pass).
  double pitch_response_departure(int b) const { return response_departure_[b]; }

 private:
  bool twin_usable(const FrameSample& s) const;  // the generator speed can stand in for the rotor speed
  /// Blade b's departure from its actuator's response, updated with this sample; then the response is
  /// stepped over the sample period with this sample's reference (held until the next one).
  double response_departure(int b, const FrameSample& s, double lowpass);

  SuspectInputConfig c_;
  double dt_;
  SuspectHold hold_;
  double speed_mismatch_lp_ = 0.0;
  std::array<double, 3> pitch_mismatch_lp_{};
  std::array<PitchActuator, 3> response_{};
  std::array<bool, 3> response_started_{};
  std::array<double, 3> response_departure_{};
  double last_t_ = -1.0;
  uint64_t suspect_samples_ = 0;
};

}  // namespace windfdi::blade_load
