// Plant scenarios (YAML): duration, seed, turbines with their wind, and the faults to inject.
#pragma once

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "turbine_params.hpp"
#include "yaml_config.hpp"

namespace windfdi::plant {

struct WindConfig {
  double mean = 12.0;                  ///< m/s at hub height
  double turbulence_intensity = 0.1;   ///< std / mean (-)
  double length_scale = 340.0;         ///< m; turbulence time constant = length_scale / mean
  double shear_exponent = 0.2;         ///< vertical power law v(h) = v_hub (h/H)^alpha
  double shear_variation = 0.0;        ///< std of the shear exponent's slow variation (-)
  double shear_time_constant = 300.0;  ///< s, correlation time of that variation
  double tower_shadow = 0.1;           ///< relative wind deficit at the tower (azimuth pi)
  double lidar_distance = 100.0;       ///< m upstream of the rotor
  double lidar_rate = 10.0;            ///< Hz
  double lidar_noise = 0.1;            ///< m/s std per beam
};

/// One injected fault. `type` decides which parameters matter (documented in deploy/scenarios/README.md).
struct FaultSpec {
  std::string turbine;
  std::string target;  ///< a measured channel, pitch_actuator_i, rotor, converter, drive_train, lidar
  std::string type;
  double start = 0.0;  ///< s
  double end = 1e300;  ///< s (absent: to the end)
  double value = 0.0;  ///< bias / offset / stuck value / torque offset / efficiency / ice mass ...
  bool has_value = false;
  double gain = 1.0;       ///< gain, and intermittent's on-phase gain
  double rate = 0.0;       ///< drift per second (channel unit / s)
  double amplitude = 0.0;  ///< bias_paper: the share of eqs 41-42 (0.02 drive train, 0.05 pitch)
  double period = 20.0;    ///< intermittent: s
  double duty = 0.3;       ///< intermittent: share of the period the fault is on
  double ramp_in = 0.0;    ///< s (pitch actuator faults, ice accretion)
  double ramp_out = 0.0;   ///< s (pitch actuator faults)
  double alpha = 1.0;      ///< pitch actuator: final fault indicator (0..1)
  double fraction = 1.0;   ///< ice shedding: share of the ice that falls off
  std::string label() const { return target + ":" + type; }

  /// A fault of `type` on `target` of `turbine` from `start` (s), the rest at its defaults, as a scenario
  /// file with only those keys would give it.
  static FaultSpec make(std::string turbine, std::string target, std::string type, double start) {
    FaultSpec f;
    f.turbine = std::move(turbine);
    f.target = std::move(target);
    f.type = std::move(type);
    f.start = start;
    return f;
  }
  FaultSpec& with_value(double v) {
    value = v;
    has_value = true;
    return *this;
  }
};

struct TurbineScenario {
  std::string id;
  WindConfig wind;
  double ice_mass = 0.0;  ///< kg present at the start
};

struct Scenario {
  std::string file;
  double duration = 600.0;  ///< s
  uint64_t seed = 1;
  double sample_rate = 100.0;  ///< Hz
  std::string turbine_file;    ///< resolved path
  TurbineParams turbine;
  std::vector<TurbineScenario> turbines;
  std::vector<FaultSpec> faults;
  std::vector<FaultSpec> faults_of(const std::string& turbine_id) const;
};

/// Measured channels that sensor faults may target.
const std::vector<std::string>& sensor_channels();
/// Valid fault types for a target.
std::vector<std::string> fault_types_for(const std::string& target);

/// Loads a scenario; `deploy_dir` resolves a relative `turbine_file` and the default turbine.
/// Unknown keys, targets or types, and impossible values, are ConfigErrors naming file, line and key.
Scenario load_scenario(const std::string& path, const std::string& deploy_dir);

}  // namespace windfdi::plant
