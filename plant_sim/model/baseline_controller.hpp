// The benchmark turbine's baseline controller: K omega^2 torque below rated, gain-scheduled PI pitch above,
// individual pitch control on the 1P blade load (from the strain gauges or the LIDAR load model), and the
// arbiter's modes (degraded, safe stop, corrected speed, ice-adapted gains, per-blade rate limits).
#pragma once

#include <array>
#include <deque>

#include "control_modes.hpp"
#include "frame_sample.hpp"
#include "turbine_params.hpp"

namespace windfdi::plant {

using control::IpcSource;  // common/control_modes.hpp, shared with the arbiter
using control::OperatingMode;

/// What the arbiter's ControlConfiguration asks of the controller (defaults: no arbiter).
struct ControlInput {
  OperatingMode mode = OperatingMode::kNormal;
  IpcSource ipc_source = IpcSource::kStrainGauge;
  std::array<double, 3> pitch_rate_limit{10.0, 10.0, 10.0};  ///< deg/s per blade, limits the pitch demand
  bool use_corrected_generator_speed = false;
  double corrected_generator_speed = kNaN;  ///< rad/s, from wt/estimate/sensor_bias
  double inertia = 0.0;              ///< kg m^2 generator side for the ice-adapted controller (0: nominal)
  double torque_compensation = 0.0;  ///< N m taken off the converter's torque command (a converter offset)
};

/// Baseline controller gains (plant_sim/README.md).
struct ControllerParams {
  double pitch_kp = 1.0;             ///< deg per rad/s of generator speed error
  double pitch_ki = 0.4;             ///< deg per (rad/s * s)
  double gain_schedule_pitch = 6.3;  ///< deg: gains divided by (1 + beta / this)
  double speed_filter = 0.1;         ///< s, low-pass time constant on measured generator speed
  double ipc_gain = 2e-7;            ///< deg per (N m * s): integral gain of the 1P (d-q) loop
  double ipc_limit = 3.0;            ///< deg, largest IPC pitch offset
  double degraded_power = 0.7;       ///< share of rated power in degraded mode
  double degraded_speed = 0.9;       ///< share of rated generator speed in degraded mode
  double stop_torque_time = 10.0;    ///< s, time constant of the torque's decay in a safe stop, which also
                                     ///< drops 1 N m per sample so that it ends: from rated torque (30 kN m)
                                     ///< zero after 10 ln(31) = 34 s at 100 Hz
};

/// The references for the next sample (held over it).
struct ControllerOutput {
  std::array<double, 3> pitch_ref{};  ///< deg per blade
  double torque_ref = 0.0;            ///< N m generator torque
};

class BaselineController {
 public:
  /// `lidar_distance` (m) and `fallback_wind` (m/s, the wind assumed before a LIDAR measurement) serve the
  /// LIDAR-model IPC; dt is the sample period (s).
  BaselineController(const TurbineParams& turbine, const ControllerParams& params, double lidar_distance,
                     double fallback_wind, double dt);

  /// Starts at a steady operating point: collective pitch (deg) and generator speed (rad/s).
  void start_at(double pitch, double generator_speed);

  /// One sample at time t (s): the measured sample (its LIDAR speeds are new when `lidar_updated`), and the
  /// converter's present torque (N m), from which a safe stop ramps down.
  ControllerOutput step(double t, const ControlInput& input, const FrameSample& measured, bool lidar_updated,
                        double converter_torque);

 private:
  /// The 1P blade loads IPC acts on, from the source the arbiter chose; false when they are not known.
  bool ipc_moments(double t, const ControlInput& input, const FrameSample& measured,
                   std::array<double, 3>& moment) const;
  /// The demand moved from the last one no faster than the arbiter's per-blade rate limit.
  std::array<double, 3> derated(std::array<double, 3> demand, const ControlInput& input) const;

  TurbineParams p_;
  AeroModel aero_;
  ControllerParams ctl_;
  double lidar_distance_, fallback_wind_, dt_;
  double pitch_gain_scale_ = 1.0;  // the turbine's J omega / P over the benchmark's
  double speed_filtered_ = 0, pitch_integral_ = 0, ipc_d_ = 0, ipc_q_ = 0, stop_torque_ = -1;
  std::array<double, 3> pitch_ref_{};
  double lidar_upper_ = kNaN, lidar_lower_ = kNaN;   // the last LIDAR measurement
  std::deque<std::array<double, 3>> lidar_history_;  // (t, upper, lower) for the LIDAR-model IPC
};

}  // namespace windfdi::plant
