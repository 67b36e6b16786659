// windfdi-sensor-bias's service spec: one BiasEstimator per turbine, estimates at frame rate with corrected
// values.
#include "sensor_bias_service.hpp"

#include <memory>

#include "Estimates.h"
#include "csv.hpp"
#include "dds/endpoints.hpp"
#include "deploy_dir.hpp"

namespace windfdi::sensor_bias {

namespace {

class BiasDiagnoser : public TurbineDiagnoser {
 public:
  BiasDiagnoser(const BiasConfig& c, const GainFile& dt, const GainFile& p, const TurbineParams& t)
      : est_(c, dt, p, t) {}
  bool update(const FrameSample& s, bool gap, std::vector<FaultEvent>& events) override {
    fresh_ = true;
    return est_.update(s, gap, events);
  }
  bool estimate_due(std::vector<std::string>& values) override {
    if (!fresh_ || !est_.has_output()) return false;
    fresh_ = false;
    const auto& o = est_.output();
    values.clear();
    for (double b : o.bias) values.push_back(format_number(b));
    for (double c : o.corrected) values.push_back(format_number(c));
    values.push_back(format_number(o.bound_ratio));
    values.push_back(format_number(o.aero_torque));
    return true;
  }
  void set_context(const InputContext& context, double t) override { est_.set_context(context, t); }
  const BiasOutput& last() const { return est_.output(); }

 private:
  BiasEstimator est_;
  bool fresh_ = false;
};

struct State {
  TurbineParams turbine;
  BiasConfig config;
  GainFile drive_train, pitch;
};

}  // namespace

ServiceSpec sensor_bias_spec() {
  auto state = std::make_shared<State>();
  ServiceSpec spec;
  spec.name = "sensor_bias";
  spec.description =
      "Speed and pitch sensor biases with a quadratic-boundedness observer (Witczak, Pazera, Puig, "
      "Mrugalski)";
  // The replay contract's five columns first, then the corrected measurements, the bound ratio and the input
  // used.
  spec.estimate_columns = {"bias_rotor_speed",
                           "bias_generator_speed",
                           "bias_pitch_1",
                           "bias_pitch_2",
                           "bias_pitch_3",
                           "corrected_rotor_speed",
                           "corrected_generator_speed",
                           "corrected_pitch_1",
                           "corrected_pitch_2",
                           "corrected_pitch_3",
                           "bound_ratio",
                           "aero_torque_input"};
  spec.configure = [state](const YamlSection& cfg) {
    state->turbine = configured_turbine(cfg);
    state->config = load_bias_config(cfg, deploy_dir() + "/sensor_bias");
    state->drive_train = load_gain_file(state->config.drive_train_gain_file);
    state->pitch = load_gain_file(state->config.pitch_gain_file);
    // Construct once so a gain file of the wrong shape fails at start-up, not at the first sample.
    BiasEstimator check(state->config, state->drive_train, state->pitch, state->turbine);
  };
  spec.make = [state](const std::string&) -> std::unique_ptr<TurbineDiagnoser> {
    return std::make_unique<BiasDiagnoser>(state->config, state->drive_train, state->pitch, state->turbine);
  };
  spec.make_publisher = [](bus::Participant& participant) -> EstimatePublisher {
    auto writer = std::make_shared<bus::Writer<windfdi::SensorBiasEstimate>>(participant);
    return [writer](const std::string& id, double, TurbineDiagnoser& d) {
      const auto& o = static_cast<BiasDiagnoser&>(d).last();
      windfdi::SensorBiasEstimate e;
      e.t(o.t);
      e.turbine_id(id);
      e.bias_rotor_speed(o.bias[0]);
      e.bias_generator_speed(o.bias[1]);
      e.bias_pitch({o.bias[2], o.bias[3], o.bias[4]});
      e.corrected_rotor_speed(o.corrected[0]);
      e.corrected_generator_speed(o.corrected[1]);
      e.corrected_pitch({o.corrected[2], o.corrected[3], o.corrected[4]});
      e.bound_ratio(o.bound_ratio);
      writer->write(e);
    };
  };
  return spec;
}

}  // namespace windfdi::sensor_bias
