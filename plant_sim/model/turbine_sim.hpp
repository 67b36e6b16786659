// One simulated benchmark turbine: its wind (wind_field), dynamics (drive_train), sensors (sensors) and
// baseline controller (baseline_controller) put together with the aerodynamics, blade loads, icing and the
// scenario's plant faults. No DDS; time advances by step().
#pragma once

#include <array>
#include <deque>
#include <string>
#include <vector>

#include "baseline_controller.hpp"
#include "drive_train.hpp"
#include "frame_sample.hpp"
#include "random_source.hpp"
#include "scenario.hpp"
#include "sensors.hpp"
#include "turbine_params.hpp"
#include "wind_field.hpp"

namespace windfdi::plant {

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
  bool lidar_updated() const { return wind_.lidar_updated(); }
  double lidar_distance() const { return wind_.config().lidar_distance; }
  const std::string& id() const { return id_; }
  double time() const { return t_; }

  /// Truth column names for a recording: true_*, aero_torque, aero_power, fault_active_<target>_<type>.
  std::vector<std::string> truth_columns() const;
  /// Values in the order of truth_columns().
  std::vector<double> truth_values() const;
  /// Whether each scenario fault is active now (same order as the fault list).
  std::vector<bool> faults_active() const;

 private:
  void settle(double seconds);
  void advance(const ControlInput& input, bool inject_faults);

  std::string id_;
  TurbineParams p_;
  AeroModel aero_;
  std::vector<FaultSpec> faults_;
  NoiseParams noise_;
  double dt_;
  RandomSource random_;
  WindField wind_;
  Sensors sensors_;
  BaselineController controller_;

  double t_ = 0.0;
  int64_t index_ = 0;  // sample index; negative while settling
  uint64_t k_ = 0;     // samples since t = 0 (the sequence number)
  // Plant state.
  DriveTrain drive_train_;
  double gen_torque_ = 0;  // converter output (N m)
  std::array<PitchActuator, 3> actuator_{};
  double azimuth_ = 0;  // rad, blade 1
  double ice_mass_ = 0, ice_initial_ = 0, ice_shed_ = 0;
  std::vector<bool> shed_done_;
  // 1P truth: one revolution of (d azimuth, M cos, M sin) per blade.
  std::deque<std::array<double, 7>> revolution_;
  std::array<double, 7> revolution_sum_{};

  FrameSample sample_;
  Truth truth_;
};

}  // namespace windfdi::plant
