// windfdi-sensor-bias's service spec: one BiasEstimator per turbine, estimates at frame rate with corrected
// values.
#include "sensor_bias_service.hpp"

#include <spdlog/spdlog.h>

#include <memory>

#include "deploy_dir.hpp"
#include "sensor_bias_estimate_topic.hpp"

namespace windfdi::sensor_bias {

namespace {
using Idl = windfdi::SensorBiasEstimate;
using E = BiasOutput;

struct State {
  TurbineParams turbine;
  BiasConfig config;
  GainFile drive_train, pitch;
};

std::array<double, 3> pitch_part(const std::array<double, kChannels>& v) { return {v[2], v[3], v[4]}; }
}  // namespace

ServiceSpec sensor_bias_spec() {
  auto state = std::make_shared<State>();
  TypedService<BiasEstimator, E, Idl> s;
  s.name = "sensor_bias";
  s.description =
      "Speed and pitch sensor biases with a quadratic-boundedness observer (Witczak, Pazera, Puig, "
      "Mrugalski)";
  s.inputs = {
      {"the drive-train observer: rotor- and generator-speed sensor faults",
       {"rotor_speed", "generator_speed", "gen_torque"},
       true,
       "the speed sensors are not diagnosed"},
      {"the aerodynamic torque model on the anemometer, the drive-train observer's input",
       {"wind_hub"},
       false,
       "the recording's aero_torque column is needed instead, or the speed sensors are not diagnosed"},
      {"the power witness P / (eta_g T_g): a bias common to both speed sensors, gain against offset",
       {"power"},
       false,
       "a bias common to both speed sensors goes unseen, and a speed fault is reported as an offset "
       "(sensor_bias) at type_decision_time"},
  };
  for (auto& u : per_blade({"the pitch observer of blade {blade}: its pitch sensor's faults",
                            {"pitch", "pitch_ref"},
                            true,
                            "blade {blade}'s pitch sensor is not diagnosed"}))
    s.inputs.push_back(u);
  // The replay contract's five columns first, then the corrected measurements, the bound ratio and the
  // aerodynamic torque the observer was driven with (CSV only: a diagnostic of the model, not for the bus).
  s.fields = {
      number_field<E, Idl>(
          "bias_rotor_speed", [](const E& e) { return e.bias[0]; },
          [](Idl& o, double v) { o.bias_rotor_speed(v); }),
      number_field<E, Idl>(
          "bias_generator_speed", [](const E& e) { return e.bias[1]; },
          [](Idl& o, double v) { o.bias_generator_speed(v); }),
      per_blade_numbers<E, Idl>(
          "bias_pitch", [](const E& e) { return pitch_part(e.bias); },
          [](Idl& o, const auto& v) { o.bias_pitch(v); }),
      number_field<E, Idl>(
          "corrected_rotor_speed", [](const E& e) { return e.corrected[0]; },
          [](Idl& o, double v) { o.corrected_rotor_speed(v); }),
      number_field<E, Idl>(
          "corrected_generator_speed", [](const E& e) { return e.corrected[1]; },
          [](Idl& o, double v) { o.corrected_generator_speed(v); }),
      per_blade_numbers<E, Idl>(
          "corrected_pitch", [](const E& e) { return pitch_part(e.corrected); },
          [](Idl& o, const auto& v) { o.corrected_pitch(v); }),
      number_field<E, Idl>(
          "bound_ratio", [](const E& e) { return e.bound_ratio; },
          [](Idl& o, double v) { o.bound_ratio(v); }),
      {{"aero_torque_input"},
       [](const E& e, std::vector<std::string>& v) { v.push_back(format_number(e.aero_torque)); },
       nullptr},
  };
  s.configure = [state](const YamlSection& cfg) {
    state->turbine = configured_turbine(cfg);
    state->config = load_bias_config(cfg, deploy_dir() + "/sensor_bias", state->turbine);
    state->drive_train = load_gain_file(state->config.drive_train_gain_file);
    state->pitch = load_gain_file(state->config.pitch_gain_file);
    if (state->config.mode == Mode::kObserver) {
      // A gain is a model of the turbine: the shipped one is the benchmark turbine's. A turbine file alone
      // must do for another turbine, so its gains are designed here when the configured ones do not fit.
      const std::string turbine_file = configured_turbine_file(cfg);
      const auto fit = [&](GainFile& gain, const char* key, const std::string& design) {
        std::string note;
        gain = gain_for_turbine(gain, key, design, turbine_file, state->turbine,
                                state->config.design_for_turbine, note);
        if (!note.empty()) spdlog::info("sensor_bias: {}", note);
      };
      fit(state->drive_train, "drive_train_gains", state->config.drive_train_design);
      fit(state->pitch, "pitch_gains", state->config.pitch_design);
    }
    // Construct once so a gain file of the wrong shape fails at start-up, not at the first sample.
    BiasEstimator check(state->config, state->drive_train, state->pitch, state->turbine);
  };
  s.make = [state](const std::string&) {
    return std::make_unique<BiasEstimator>(state->config, state->drive_train, state->pitch, state->turbine);
  };
  return service_spec(std::move(s));
}

}  // namespace windfdi::sensor_bias
