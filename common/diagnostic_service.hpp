// The shared main of every diagnostic service: replay mode (the offline contract) or a DDS node, one
// diagnoser per turbine, configuration from YAML. A service supplies a ServiceSpec and nothing else.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "dds/endpoints.hpp"
#include "dds/participant.hpp"
#include "estimate_fields.hpp"
#include "fault_event.hpp"
#include "frame_sample.hpp"
#include "input_context.hpp"
#include "input_uses.hpp"
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
  /// True when an estimate is due after the last update (the service's output rate).
  virtual bool estimate_due() = 0;
  /// The last estimate, one text per estimate column. Formatted only when asked: on DDS the estimate goes
  /// out as its sample, and formatting every field of every 100 Hz estimate was string work on the hot path.
  virtual void estimate_values(std::vector<std::string>& values) const = 0;
  /// What other services and the arbiter say about this turbine's inputs, in force from sample time `t`
  /// (input_context.hpp). A core that relies on a suspect input holds its judgement; the default ignores it.
  virtual void set_context(const InputContext& context, double t) {
    (void)context;
    (void)t;
  }
};

/// Publishes a turbine's current estimate on DDS (created once per process with the participant).
using EstimatePublisher = std::function<void(const std::string& turbine_id, TurbineDiagnoser& d)>;

struct ServiceSpec {
  std::string name;                           ///< canonical service name, e.g. "pitch_diag"
  std::string description;                    ///< one line for --help
  std::vector<std::string> estimate_columns;  ///< replay estimate columns after t and turbine_id
  bool wants_lidar = false;                   ///< merge wt/lidar into the samples
  /// What it does with each input: said at start per recording or turbine; a recording with no essential
  /// use's inputs exits 2 naming them.
  std::vector<InputUse> inputs;
  /// Reads the service's configuration (without --config an empty section: every key at its default).
  /// Called once, before make().
  std::function<void(const YamlSection& config)> configure;
  std::function<std::unique_ptr<TurbineDiagnoser>(const std::string& turbine_id)> make;
  std::function<EstimatePublisher(bus::Participant& participant)> make_publisher;
};

/// One turbine's diagnosis by a service's core. Every core has the same shape:
///   bool update(const FrameSample&, bool gap, std::vector<FaultEvent>&)  (false: the sample was rejected)
///   bool estimate_due(Estimate&)                                        (at the service's output rate)
///   void set_context(const InputContext&, double t)
/// and its estimate one field list (estimate_fields.hpp) from which the replay columns and the DDS sample
/// (`Idl`, with t and turbine_id) both come.
template <class Core, class Estimate, class Idl>
class CoreDiagnoser final : public TurbineDiagnoser {
 public:
  CoreDiagnoser(std::unique_ptr<Core> core, const EstimateFields<Estimate, Idl>& fields)
      : core_(std::move(core)), fields_(fields) {}
  bool update(const FrameSample& sample, bool gap, std::vector<FaultEvent>& events) override {
    return core_->update(sample, gap, events);
  }
  bool estimate_due() override { return core_->estimate_due(last_); }
  void estimate_values(std::vector<std::string>& values) const override {
    values.clear();
    csv_values(fields_, last_, values);
  }
  void set_context(const InputContext& context, double t) override { core_->set_context(context, t); }
  /// The last estimate as its DDS sample.
  Idl sample(const std::string& turbine_id) const {
    Idl out;
    out.t(last_.t);
    out.turbine_id(turbine_id);
    put_fields(fields_, last_, out);
    return out;
  }

 private:
  std::unique_ptr<Core> core_;
  const EstimateFields<Estimate, Idl>& fields_;
  Estimate last_{};
};

/// What a service is, typed: its names, its estimate's fields, how it reads its configuration (once) and
/// makes one turbine's core.
template <class Core, class Estimate, class Idl>
struct TypedService {
  std::string name;         ///< canonical service name, e.g. "pitch_diag"
  std::string description;  ///< one line for --help
  bool wants_lidar = false;
  std::vector<InputUse> inputs;  ///< ServiceSpec::inputs
  EstimateFields<Estimate, Idl> fields;
  std::function<void(const YamlSection& config)> configure;
  std::function<std::unique_ptr<Core>(const std::string& turbine_id)> make;
};

/// The ServiceSpec the shared main runs, from a typed service.
template <class Core, class Estimate, class Idl>
ServiceSpec service_spec(TypedService<Core, Estimate, Idl> typed) {
  using Diagnoser = CoreDiagnoser<Core, Estimate, Idl>;
  const auto s = std::make_shared<const TypedService<Core, Estimate, Idl>>(std::move(typed));
  ServiceSpec spec;
  spec.name = s->name;
  spec.description = s->description;
  spec.estimate_columns = csv_columns(s->fields);
  spec.wants_lidar = s->wants_lidar;
  spec.inputs = s->inputs;
  spec.configure = s->configure;
  spec.make = [s](const std::string& id) -> std::unique_ptr<TurbineDiagnoser> {
    return std::make_unique<Diagnoser>(s->make(id), s->fields);
  };
  spec.make_publisher = [](bus::Participant& participant) -> EstimatePublisher {
    auto writer = std::make_shared<bus::Writer<Idl>>(participant);
    // Every diagnoser this spec runs was made by spec.make above: a Diagnoser.
    return [writer](const std::string& id, TurbineDiagnoser& d) {
      writer->write(static_cast<Diagnoser&>(d).sample(id));
    };
  };
  return spec;
}

/// Parses the command line (common options, --config, --replay, --estimates, --events) and runs.
int run_diagnostic_service(int argc, char** argv, const ServiceSpec& spec);

}  // namespace windfdi
