// One turbine's converter and drive-train diagnosis, shaped like every service core: frame samples in
// (checked, with the turbine model's aerodynamic power on a centred anemometer average), estimates and
// fault events out.
#pragma once

#include <cstdint>
#include <vector>

#include "aero_power_input.hpp"
#include "converter_monitor.hpp"
#include "efficiency_monitor.hpp"
#include "fault_event.hpp"
#include "frame_sample.hpp"
#include "input_context.hpp"
#include "running_stats.hpp"
#include "turbine_params.hpp"
#include "yaml_config.hpp"

namespace windfdi::drive_train {

struct DiagnoserConfig {
  ConverterConfig converter;
  EfficiencyConfig efficiency;
  double estimate_rate = 10.0;     ///< Hz
  double wind_window = 2.0;        ///< s, centred anemometer average before the power model
  double fixed_pitch = 0.0;        ///< deg, the turbine file's: taken for a pitch the data does not carry
  double context_lookback = 60.0;  ///< s of energy-balance blocks dropped when a speed or pitch sensor is
                                   ///< newly reported by another service (sensor_bias needs up to ~50 s)
  double sample_time = 0.01;       ///< s, the frame period (the benchmark's 100 Hz)
  /// m/s: the energy balance leaves out blocks pitched beyond what the turbine needs for rated power at
  /// rated speed in this wind (feathering, stopping); the pitch itself is the turbine's (feathering_pitch)
  double max_pitch_wind = 28.0;
  /// Relative disagreement of the two speed sensors (omega_g / N against omega_r, means over
  /// speed_pair_time) above which the energy balance holds (0: off). The balance takes omega_g, and a
  /// generator-speed offset or gain moves it at once while sensor_bias names it only once it has told the two
  /// apart (10-20 s below rated power): 10 such faults raised efficiency_loss 6-9 s after their onset in the
  /// fault suite. Healthy hours at 6, 12 and 20 m/s: at most 0.7 % over 2 s, once 1.3 % near the lowest
  /// rotor speed (the rotor sensor's noise and the shaft's torsion); the suite's faults: 3-8 %.
  double speed_pair_mismatch = 0.02;
  double speed_pair_time = 2.0;  ///< s over which each speed is averaged for it
  /// While another service reports the generator speed and not the rotor speed, the energy balance runs on
  /// the rotor's own sensor (times N) instead of stopping. Stopped, it needed three minutes of blocks after
  /// the report cleared, and an efficiency step inside a generator-speed fault or in the minutes after it
  /// was never seen: 4 of the 43 efficiency losses of fault suite sets 168-171 (false: stop, as before).
  bool rotor_speed_fallback = true;
  /// On the rotor's sensor the balance is noisier, the more so the slower and heavier the rotor: its
  /// speed noise enters each block's inertia torque. A second balance runs on it beside the generator's
  /// (while both sensors agree and neither is reported) and learns the RMS of its drop less the generator
  /// balance's; on the fallback the drop raised is at least this many times that RMS (0: efficiency_step
  /// alone). The 6 MW rotor at 6 m/s read a drop RMS of 2.4 % there (0.6 % on the generator's) and raised
  /// efficiency_loss on healthy hours.
  double rotor_speed_noise_sigmas = 3.5;
  double rotor_speed_noise_time = 1800.0;  ///< s of that second balance's drops remembered for the RMS
  /// s of them (tests, after the balance's first 180 s) before the RMS is used; until then the fallback
  /// judges nothing
  double rotor_speed_noise_min_time = 60.0;
  double max_bridged_gap = 0.5;  ///< s: samples lost over at most this long leave the energy balance's
                                 ///< block running (its span counts them); a longer hole ends the block
  // Plausible measurements: beyond them a sample is rejected (counted), never fed.
  double max_torque = 2e5;             ///< N m, |generator torque| and |its reference|
  double max_generator_speed = 400.0;  ///< rad/s
  double max_power = 2e7;              ///< W, |electrical power|
};

/// Loads the `drive_train` keys (unknown keys and out-of-range values are ConfigErrors naming file and key);
/// the drive train's values come from the turbine.
DiagnoserConfig load_diagnoser_config(const YamlSection& section, const TurbineParams& turbine);

/// The estimate (10 Hz): the replay columns and DriveTrainEstimate.
struct DriveTrainOutput {
  double t = 0.0;
  double torque_offset = 0.0;     ///< N m: while raised the estimated offset, else the residual's 1 s mean
  double torque_statistic = 0.0;  ///< CUSUM sum (noise sd units)
  double efficiency = kNaN;       ///< estimated drive-train efficiency, the last 30 s (NaN: not yet)
  double efficiency_reference = kNaN;  ///< the reference it is compared with
};

class DriveTrainDiagnoser {
 public:
  /// `aero` must outlive this object (one model per process).
  DriveTrainDiagnoser(const DiagnoserConfig& config, const AeroModel& aero);

  /// False when the sample was rejected (a NaN, infinite or implausible torque, torque reference or
  /// generator speed): counted, never fed.
  bool update(const FrameSample& s, bool gap, std::vector<FaultEvent>& events);
  bool estimate_due(DriveTrainOutput& out);
  /// A suspect generator speed takes the power witness away; the energy balance then takes the rotor's
  /// speed sensor (rotor_speed_fallback), or stops and forgets its blocks when that is suspect too or the
  /// fallback is off. A suspect pitch reading is replaced by its reference. When a sensor the balance takes
  /// is newly reported, the blocks of the last context_lookback are dropped. So they are when the two speed
  /// sensors begin to disagree (speed_pair_mismatch) with neither reported, and the balance holds until they
  /// agree again or one is reported.
  void set_context(const InputContext& context, double t);

  uint64_t rejected() const { return rejected_; }
  const ConverterState& converter() const { return converter_.state(); }
  const EfficiencyState& efficiency() const { return balance_.monitor.state(); }
  /// RMS of the drop of the balance on the rotor's sensor less the generator balance's, learned beside it
  /// (0: not yet).
  double rotor_speed_drop_rms() const;
  /// The drop the efficiency test raises now (efficiency_step, or more on the rotor's sensor).
  double efficiency_step() const { return balance_.monitor.step(); }
  /// Times the two speed sensors began to disagree (speed_pair_mismatch) with neither reported.
  uint64_t speed_disagreements() const { return disagreements_; }
  /// True while the energy balance takes the rotor's speed sensor (the generator's is reported).
  bool balance_on_rotor_speed() const { return on_rotor_speed(context_); }

 private:
  void report_converter(double t, std::vector<FaultEvent>& events);
  void report_efficiency(double t, std::vector<FaultEvent>& events);
  bool on_rotor_speed(const InputContext& context) const {
    return c_.rotor_speed_fallback && context.generator_speed_suspect && !context.rotor_speed_suspect;
  }

  /// One energy balance: the power model on its centred wind (and speed) average, and the step test.
  struct Balance {
    Balance(const DiagnoserConfig& c, const AeroModel& aero, const EfficiencyConfig& e)
        : power(aero, c.wind_window, c.sample_time), monitor(e, c.sample_time) {}
    AeroPowerInput power;
    EfficiencyMonitor monitor;
    double last_centre_t = kNaN;        // time of the last sample judged
    uint64_t last_centre_sequence = 0;  // and its sequence
  };
  /// Pushes `fed` (its rotor speed the balance's) into the balance's power model; true with the sample half
  /// a wind window back, its aerodynamic power, whether a hole before it broke the block (`broken`) and the
  /// samples lost in a bridged one.
  bool centre_sample(Balance& b, const FrameSample& fed, bool gap, FrameSample& centre, double& aero_power,
                     bool& broken, uint64_t& lost) const;
  void update_rotor_shadow(FrameSample fed, double rotor_reading, bool gap, bool speeds_healthy);
  void update_step();

  DiagnoserConfig c_;
  ConverterMonitor converter_;
  Balance balance_;       // the efficiency test: omega_g / N, or the rotor's sensor on the fallback
  Balance rotor_shadow_;  // the rotor's sensor beside it, for its noise (its own test never raises)
  uint64_t shadow_tests_seen_ = 0;
  double shadow_drop_square_ = 0.0;  // mean square of its drop less the main's, over rotor_speed_noise_time
  double shadow_blocks_ = 0.0;       // drops learned (capped at rotor_speed_noise_time's blocks)
  InputContext context_;
  bool last_rejected_ = false;
  uint64_t rejected_ = 0;
  double t_ = 0.0, next_estimate_ = 0.0, converter_since_ = 0.0, efficiency_since_ = 0.0;
  bool have_estimate_ = false;
  RunningMean pair_rotor_, pair_generator_;  // the two speeds over the current speed_pair_time
  bool speeds_disagree_ = false;
  // The balance's speed source changed at this sample time: the samples within half a wind window of it
  // reach the balance averaged over both sensors and are left out (NaN: no change under way).
  double source_switch_t_ = kNaN;
  uint64_t disagreements_ = 0;
};

}  // namespace windfdi::drive_train
