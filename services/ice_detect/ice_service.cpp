// windfdi-ice-detect's service spec: one IceTurbine per turbine, 1 Hz InertiaEstimate.
#include "ice_service.hpp"

#include <memory>

#include "ice_detect_estimate_topic.hpp"

namespace windfdi::ice_detect {

namespace {
using Idl = windfdi::InertiaEstimate;
using E = InertiaOutput;

struct State {
  TurbineParams turbine;
  DetectorConfig config;
  std::unique_ptr<AeroModel> aero;
};
}  // namespace

ServiceSpec ice_detect_spec() {
  auto state = std::make_shared<State>();
  TypedService<IceTurbine, E, Idl> s;
  s.name = "ice_detect";
  s.description = "Ice accretion and shedding from the estimated rotor inertia (Stotsky & Egardt 2013)";
  s.inputs = {
      {"the inertia regression (Stotsky & Egardt eq 2)",
       {"generator_speed", "gen_torque"},
       true,
       "no ice diagnosis"},
      {"the aerodynamic power model on the anemometer",
       {"wind_hub", "rotor_speed"},
       false,
       "the recording's aero_power column is needed instead, or no ice diagnosis"},
      {"each blade's pitch in the power model",
       {"pitch_1", "pitch_2", "pitch_3"},
       false,
       "the rotor is taken as fixed-pitch at absent_pitch (a stall-regulated or fixed-pitch machine)"},
  };
  s.fields = {
      number_field<E, Idl>(
          "inertia", [](const E& e) { return e.inertia; }, [](Idl& o, double v) { o.inertia(v); }),
      number_field<E, Idl>(
          "ice_mass", [](const E& e) { return e.ice_mass; }, [](Idl& o, double v) { o.ice_mass(v); }),
      flag_field<E, Idl>(
          "excited", [](const E& e) { return e.excited; }, [](Idl& o, bool v) { o.excited(v); }),
      // The clean rotor's inertia J0 goes to the bus only (the arbiter's ice-adapted gains); a replay
      // reads it from the configuration.
      {{}, nullptr, [](const E& e, Idl& o) { o.inertia_clean(e.inertia_clean); }},
      // The configured levels, bus only, so that a plot of the estimate shows this turbine's own thresholds.
      {{},
       nullptr,
       [state](const E&, Idl& o) {
         o.warning_rise(state->config.warning_rise);
         o.fault_rise(state->config.fault_rise);
         o.critical_rise(state->config.critical_rise);
       }},
  };
  s.configure = [state](const YamlSection& cfg) {
    state->turbine = configured_turbine(cfg);
    state->config = load_detector_config(cfg, state->turbine);
    state->aero = std::make_unique<AeroModel>(state->turbine);
  };
  s.make = [state](const std::string&) {
    return std::make_unique<IceTurbine>(state->config, state->turbine, *state->aero);
  };
  return service_spec(std::move(s));
}

}  // namespace windfdi::ice_detect
