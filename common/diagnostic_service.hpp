// The shared main of every diagnostic service: replay mode (the offline contract) or a DDS node, one
// diagnoser per turbine, configuration from YAML. A service supplies a ServiceSpec and nothing else.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "dds/participant.hpp"
#include "fault_event.hpp"
#include "frame_sample.hpp"
#include "input_context.hpp"
#include "turbine_params.hpp"
#include "yaml_config.hpp"

namespace windfdi {

/// One turbine's diagnosis, wrapping a service's core.
class TurbineDiagnoser {
 public:
  virtual ~TurbineDiagnoser() = default;
  /// Feeds one sample (`gap`: samples were lost before it). Returns false when the sample was rejected
  /// (NaN, infinite, out of range: counted, never fed to an estimator). Appends raised/cleared events.
  virtual bool update(const FrameSample& sample, bool gap, std::vector<FaultEvent>& events) = 0;
  /// True when an estimate is due after the last update (the service's output rate); then `values`
  /// holds one text per estimate column.
  virtual bool estimate_due(std::vector<std::string>& values) = 0;
  /// What other services and the arbiter say about this turbine's inputs, in force from sample time `t`
  /// (input_context.hpp). A core that relies on a suspect input holds its judgement; the default ignores it.
  virtual void set_context(const InputContext& context, double t) {
    (void)context;
    (void)t;
  }
};

/// Publishes a turbine's current estimate on DDS (created once per process with the participant).
using EstimatePublisher = std::function<void(const std::string& turbine_id, double t, TurbineDiagnoser& d)>;

struct ServiceSpec {
  std::string name;                           ///< canonical service name, e.g. "pitch_diag"
  std::string description;                    ///< one line for --help
  std::vector<std::string> estimate_columns;  ///< replay estimate columns after t and turbine_id
  bool wants_lidar = false;                   ///< merge wt/lidar into the samples
  /// Reads the service's configuration (without --config an empty section: every key at its default).
  /// Called once, before make().
  std::function<void(const YamlSection& config)> configure;
  std::function<std::unique_ptr<TurbineDiagnoser>(const std::string& turbine_id)> make;
  std::function<EstimatePublisher(bus::Participant& participant)> make_publisher;
};

/// The turbine a service configuration names in `turbine_file` (relative: beside the configuration), else
/// the shipped benchmark turbine (deploy_dir()/turbine/benchmark_4.8MW.yaml).
TurbineParams configured_turbine(const YamlSection& config);

/// Parses the command line (common options, --config, --replay, --estimates, --events) and runs.
int run_diagnostic_service(int argc, char** argv, const ServiceSpec& spec);

}  // namespace windfdi
