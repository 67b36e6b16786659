// Converter torque offset (the FDI/FTC benchmark's fault 8): the measured generator torque against the
// converter's first-order response to its torque reference, tested by a two-sided CUSUM, with the electrical
// power as a second witness.
#pragma once

#include <cstdint>
#include <vector>

#include "running_stats.hpp"

namespace windfdi::drive_train {

struct ConverterConfig {
  double time_constant = 0.02;         ///< s, the converter's first-order response (turbine file)
  double generator_efficiency = 0.98;  ///< eta_g: power = eta_g omega_g T_g (turbine file)
  double min_offset = 100.0;           ///< N m, the smallest offset to detect: the CUSUM's design shift
  double cusum_threshold = 16.0;       ///< h, in units of the torque noise's standard deviation
  double noise_learn_time = 60.0;  ///< s of residual from which the torque noise is learned (median absolute
                                   ///< deviation: an offset present from the start does not inflate it)
  double noise_floor = 5.0;        ///< N m, smallest noise the CUSUM is scaled with
  double witness_ratio = 0.5;      ///< the power's offset must lie within [ratio, 1 / ratio] of the torque's
  double clear_time = 3.0;         ///< s the offset (1 s mean) must stay below half min_offset to clear
  double min_generator_speed = 30.0;  ///< rad/s; below it the power witness is not read
};

/// What the converter monitor says after a sample.
struct ConverterState {
  bool learned = false;  ///< the torque noise is known and the CUSUM runs
  bool raised = false;
  bool changed = false;  ///< raised or cleared by this sample
  double offset = 0.0;   ///< N m, estimated offset (the witness's when it confirmed, else the torque's)
  double witness_offset = 0.0;  ///< N m, the power channel's estimate over the same samples
  double statistic = 0.0;       ///< larger CUSUM sum (noise sd units)
  double noise = 0.0;           ///< N m, learned torque noise sd
  double residual_mean = 0.0;   ///< N m, 1 s mean of the torque residual
};

class ConverterMonitor {
 public:
  ConverterMonitor(const ConverterConfig& config, double sample_time);

  /// One sample: measured torque and its reference (N m), generator speed (rad/s) and power (W); the speed
  /// or power may be NaN (no witness). `witness_trusted` false while the generator speed is suspect: the
  /// torque channel decides alone. After a gap the converter model restarts from the measurement.
  const ConverterState& update(double torque, double torque_ref, double generator_speed, double power,
                               bool witness_trusted, bool gap);
  const ConverterState& state() const { return state_; }

 private:
  void reset_run();

  ConverterConfig c_;
  double dt_, decay_;
  bool have_model_ = false;
  double model_ = 0.0, last_ref_ = 0.0;
  std::vector<double> learn_;         // residuals while learning the noise
  double upper_ = 0.0, lower_ = 0.0;  // CUSUM sums
  // Since each sum last left zero: the residual and the power channel's offset, summed for the estimate.
  RunningMean upper_torque_, lower_torque_;
  // The power's offsets of each run: their mean must confirm the torque's, and the size is read on their
  // newer half (a run may start a few samples before the onset, while the sum wanders above zero on noise).
  std::vector<double> upper_witness_, lower_witness_;
  double mean_1s_ = 0.0, power_mean_1s_ = 0.0;  // exponential 1 s means
  bool power_mean_ok_ = false;
  double below_since_ = -1.0, t_ = 0.0;
  ConverterState state_;
};

}  // namespace windfdi::drive_train
