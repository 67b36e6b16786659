// One simulated benchmark turbine: wind and LIDAR, two-mass drive train, hydraulic pitch actuators,
// blade loads, icing, sensors with faults, and the baseline controller (with IPC). No DDS; time advances
// by step().
#pragma once

#include <array>
#include <deque>
#include <random>
#include <string>
#include <vector>

#include "control_modes.hpp"
#include "frame_sample.hpp"
#include "scenario.hpp"
#include "turbine_params.hpp"

namespace windfdi::plant {

using control::IpcSource;  // common/control_modes.hpp, shared with the arbiter
using control::OperatingMode;

/// One blade's hydraulic pitch actuator, Witczak et al. eq 34 with the -omega_n^2 beta term it lacks:
/// beta'' = -2 zeta omega_n beta' - omega_n^2 (beta - beta_ref), rate and angle limited, integrated by RK4.
struct PitchActuator {
  double angle = 0.0;  ///< deg
  double rate = 0.0;   ///< deg/s
  void step(double reference, double h, double omega_n, double zeta, double rate_limit, double min_angle,
            double max_angle);
};

/// What the arbiter's ControlConfiguration asks of the controller (defaults: no arbiter).
struct ControlInput {
  OperatingMode mode = OperatingMode::kNormal;
  IpcSource ipc_source = IpcSource::kStrainGauge;
  std::array<double, 3> pitch_rate_limit{10.0, 10.0, 10.0};  ///< deg/s per blade
  bool use_corrected_generator_speed = false;
  double corrected_generator_speed = kNaN;  ///< rad/s, from wt/estimate/sensor_bias
  double inertia = 0.0;  ///< kg m^2 generator side for the ice-adapted controller (0: nominal)
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
  double stop_torque_time = 10.0;    ///< s to ramp the generator torque to zero in a safe stop
};

/// Sensor noise (standard deviations) at the benchmark's levels.
struct NoiseParams {
  double rotor_speed = 0.025;     ///< rad/s
  double generator_speed = 0.05;  ///< rad/s
  double gen_torque = 90.0;       ///< N m
  double power = 1e3;             ///< W
  double wind_hub = 0.5;          ///< m/s
  double pitch = 0.2;             ///< deg
  double blade_moment = 2e4;      ///< N m (about 0.5 % of the rated mean flapwise moment)
};

/// True values, for honest error and delay measurements (--record-truth).
struct Truth {
  double rotor_speed = 0, generator_speed = 0, torsion = 0;
  std::array<double, 3> pitch{}, blade_moment{}, a1{};  ///< deg, N m, first-harmonic amplitude (N m)
  double inertia = 0;                                   ///< lumped, generator side (kg m^2)
  double ice_mass = 0;                                  ///< kg
  double aero_torque = 0, aero_power = 0, gen_torque = 0;
  double wind_hub = 0;       ///< at the rotor (m/s)
  double wind_upstream = 0;  ///< hub-height wind at the LIDAR plane now (m/s)
  double shear_exponent = 0;
};

class TurbineSim {
 public:
  TurbineSim(const TurbineParams& params, const TurbineScenario& turbine,
             const std::vector<FaultSpec>& faults, uint64_t seed, double sample_rate,
             const ControllerParams& controller = {}, const NoiseParams& noise = {});

  /// Advances one sample; returns the measured sample (sequence numbers from 0, t from 0).
  const FrameSample& step(const ControlInput& input = {});
  const Truth& truth() const { return truth_; }
  /// True when step() produced a new LIDAR measurement (at the LIDAR rate).
  bool lidar_updated() const { return lidar_updated_; }
  double lidar_distance() const { return wind_.lidar_distance; }
  const std::string& id() const { return id_; }
  double time() const { return t_; }

  /// Truth column names for a recording: true_*, aero_torque, aero_power, fault_active_<target>_<type>.
  std::vector<std::string> truth_columns() const;
  /// Values in the order of truth_columns().
  std::vector<double> truth_values() const;
  /// Whether each scenario fault is active now (same order as the fault list).
  std::vector<bool> faults_active() const;

 private:
  struct ChannelFaults;
  void settle(double seconds);
  void advance(const ControlInput& input, bool inject_faults);
  void update_wind();
  double pitch_alpha(const FaultSpec& f) const;
  double measure(const std::string& channel, double true_value, double noise_std, bool inject);
  bool fault_active(const FaultSpec& f) const;
  void controller(const ControlInput& input, const FrameSample& measured, std::array<double, 3>& pitch_ref,
                  double& torque_ref);

  std::string id_;
  TurbineParams p_;
  AeroModel aero_;
  WindConfig wind_;
  std::vector<FaultSpec> faults_;
  ControllerParams ctl_;
  NoiseParams noise_;
  double dt_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> normal_{0.0, 1.0};

  double t_ = 0.0;
  int64_t index_ = 0;  // sample index; negative while settling
  uint64_t k_ = 0;     // samples since t = 0 (the sequence number)
  // Wind: turbulence and shear at the LIDAR plane, delayed to the rotor (frozen turbulence).
  double turbulence_ = 0.0, shear_dev_ = 0.0;
  std::deque<std::pair<double, double>> wind_delay_;  // (hub wind, shear exponent) at the LIDAR plane
  std::size_t delay_samples_ = 1;
  double lidar_timer_ = 0.0;
  bool lidar_updated_ = false;
  double lidar_upper_ = kNaN, lidar_lower_ = kNaN;
  std::deque<std::array<double, 3>> lidar_history_;  // (t, upper, lower) for the LIDAR-model IPC

  // Plant state.
  double omega_r_ = 0, omega_g_ = 0, theta_ = 0;  // drive train
  double gen_torque_ = 0;                         // converter output (N m)
  std::array<PitchActuator, 3> actuator_{};
  double azimuth_ = 0;  // rad, blade 1
  double ice_mass_ = 0, ice_initial_ = 0, ice_shed_ = 0;
  std::vector<bool> shed_done_;
  // Controller state.
  double speed_filtered_ = 0, pitch_integral_ = 0, ipc_d_ = 0, ipc_q_ = 0, stop_torque_ = -1;
  std::array<double, 3> pitch_ref_{}, last_moment_{};
  // 1P truth: one revolution of (d azimuth, M cos, M sin) per blade.
  std::deque<std::array<double, 7>> revolution_;
  std::array<double, 7> revolution_sum_{};
  // Sensor faults: per fault, the value latched at the start of a stuck fault.
  std::vector<double> stuck_value_;
  std::vector<bool> stuck_latched_;

  FrameSample sample_;
  Truth truth_;
};

}  // namespace windfdi::plant
