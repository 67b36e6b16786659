// windfdi-plant's runner: simulates a scenario's turbines, publishes wt/frame and wt/lidar, applies the
// arbiter's ControlConfiguration (with a lease), records the replay format (with truth).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "app.hpp"
#include "scenario.hpp"

namespace windfdi::plant {

struct PlantOptions {
  std::string scenario;          ///< scenario YAML
  double rate = 1.0;             ///< simulated seconds per wall second; 0: as fast as possible
  bool offline = false;          ///< no DDS
  std::string record;            ///< replay CSV (plain or .gz) to write
  bool record_truth = false;     ///< add true_*, aero_* and fault_active_* columns
  int block = 10;                ///< samples per TurbineFrame (1..32)
  double duration = -1.0;        ///< s, overrides the scenario's when >= 0
  double config_lease = 5.0;     ///< s (wall) a ControlConfiguration stays valid without a refresh
  double progress_period = 5.0;  ///< s (wall) between progress lines (0: none)
  /// (simulated time, s): from then on the samples' time stamps are that much later (the controller's clock
  /// stepped; a test of every service's sample-time windows and timers).
  std::vector<std::pair<double, double>> clock_steps;
};

/// Parses --clock-step values "AT:SECONDS"; throws ConfigError naming a malformed one.
std::vector<std::pair<double, double>> parse_clock_steps(const std::vector<std::string>& values);

/// Parses "realtime", "max" or a factor; throws ConfigError otherwise.
double parse_rate(const std::string& text);

/// Runs the plant until the scenario's end or SIGINT/SIGTERM. Returns an exit code.
int run_plant(const CommonOptions& common, const PlantOptions& options);

}  // namespace windfdi::plant
