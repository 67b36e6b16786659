// windfdi-drive-train's service spec: one DriveTrainDiagnoser per turbine, 10 Hz DriveTrainEstimate.
#include "drive_train_service.hpp"

#include <memory>

#include "drive_train_estimate_topic.hpp"

namespace windfdi::drive_train {

namespace {
using Idl = windfdi::DriveTrainEstimate;
using E = DriveTrainOutput;

struct State {
  DiagnoserConfig config;
  std::unique_ptr<AeroModel> aero;
};
}  // namespace

ServiceSpec drive_train_spec() {
  auto state = std::make_shared<State>();
  TypedService<DriveTrainDiagnoser, E, Idl> s;
  s.name = "drive_train";
  s.description =
      "Converter torque offset and drive-train efficiency loss (the FDI/FTC benchmark's faults 8 and 9)";
  s.inputs = {
      {"the converter test: measured torque against the converter's response to its reference, power as "
       "witness",
       {"gen_torque", "gen_torque_ref", "generator_speed", "power"},
       true,
       "no converter torque-offset diagnosis"},
      {"the energy balance: electrical against aerodynamic power (efficiency)",
       {"gen_torque", "generator_speed", "wind_hub"},
       true,
       "no efficiency diagnosis (unless the recording has aero_power)"},
      {"each blade's pitch in the power model",
       {"pitch_1", "pitch_2", "pitch_3"},
       false,
       "the rotor is taken as fixed-pitch at absent_pitch"},
  };
  s.fields = {
      number_field<E, Idl>(
          "torque_offset", [](const E& e) { return e.torque_offset; },
          [](Idl& o, double v) { o.torque_offset(v); }),
      number_field<E, Idl>(
          "torque_statistic", [](const E& e) { return e.torque_statistic; },
          [](Idl& o, double v) { o.torque_statistic(v); }),
      number_field<E, Idl>(
          "efficiency", [](const E& e) { return e.efficiency; }, [](Idl& o, double v) { o.efficiency(v); }),
      number_field<E, Idl>(
          "efficiency_reference", [](const E& e) { return e.efficiency_reference; },
          [](Idl& o, double v) { o.efficiency_reference(v); }),
  };
  s.configure = [state](const YamlSection& cfg) {
    const TurbineParams turbine = configured_turbine(cfg);
    state->config = load_diagnoser_config(cfg, turbine);
    state->aero = std::make_unique<AeroModel>(turbine);
  };
  s.make = [state](const std::string&) {
    return std::make_unique<DriveTrainDiagnoser>(state->config, *state->aero);
  };
  return service_spec(std::move(s));
}

}  // namespace windfdi::drive_train
