// The command line of the plant measurement programs: [FIRST [SEEDS]] [--config FILE] [--turbine FILE]
// [--events] [--seed-offset N].
#pragma once

#include <cstdlib>
#include <string>

#include "turbine_params.hpp"
#include "yaml_config.hpp"

namespace windfdi::perf {

struct PlantMeasurementArgs {
  double first = 0.0;         ///< the program's first number (healthy hours or seconds)
  int seeds = 3;              ///< seeds per fault case
  std::string config_file;    ///< the service configuration; empty: every key at its default
  std::string turbine_file;   ///< the plant's and the service's turbine; empty: the benchmark 4.8 MW turbine
  bool print_events = false;  ///< every run's events, for a look at what went wrong
  /// Added to every random seed: runs no setting was tuned on (0: the runs the defaults were tuned with).
  uint64_t seed_offset = 0;

  /// The turbine the plant simulates and the service is configured for.
  TurbineParams turbine() const {
    return turbine_file.empty() ? TurbineParams{} : load_turbine_params_file(turbine_file);
  }
  /// The configuration section the program reads (the file, or an empty map of defaults).
  YamlSection config() const {
    return config_file.empty() ? YamlSection(YAML::Node(YAML::NodeType::Map), "(defaults)")
                               : YamlSection::load_file(config_file);
  }
};

inline PlantMeasurementArgs parse_plant_measurement_args(int argc, char** argv, double first, int seeds) {
  PlantMeasurementArgs a;
  a.first = first;
  a.seeds = seeds;
  int positional = 0;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--config" && i + 1 < argc) {
      a.config_file = argv[++i];
    } else if (arg == "--turbine" && i + 1 < argc) {
      a.turbine_file = argv[++i];
    } else if (arg == "--events") {
      a.print_events = true;
    } else if (arg == "--seed-offset" && i + 1 < argc) {
      a.seed_offset = std::strtoull(argv[++i], nullptr, 10);
    } else if (positional++ == 0) {
      a.first = std::atof(arg.c_str());
    } else {
      a.seeds = std::atoi(arg.c_str());
    }
  }
  return a;
}

}  // namespace windfdi::perf
