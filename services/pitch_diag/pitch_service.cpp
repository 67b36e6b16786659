// windfdi-pitch-diag's service spec: one PitchDiagnoser per turbine, 10 Hz PitchActuatorEstimate.
#include "pitch_service.hpp"

#include <memory>

#include "dds/convert.hpp"
#include "pitch_diag_estimate_topic.hpp"

namespace windfdi::pitch_diag {

namespace {
using Idl = windfdi::PitchActuatorEstimate;
using E = PitchEstimate;

windfdi::FaultClass idl_class(const std::string& name) {
  windfdi::FaultClass c = windfdi::FAULT_NONE;
  bus::fault_class_from_name(name, c);  // "none" and non-canonical names stay FAULT_NONE
  return c;
}
}  // namespace

ServiceSpec pitch_diag_spec() {
  auto config = std::make_shared<PitchDiagConfig>();
  TypedService<PitchDiagnoser, E, Idl> s;
  s.name = "pitch_diag";
  s.description = "Pitch-actuator fault diagnosis by model identification (Wu & Li, MIFG)";
  s.inputs = per_blade({"the identification of blade {blade}'s actuator (Wu & Li Table 1 faults)",
                        {"pitch", "pitch_ref"},
                        true,
                        "blade {blade}'s actuator is not diagnosed"});
  // The replay contract's columns first (omega_n, zeta, class), then the fault indicator and the excitation.
  s.fields = {
      per_blade_numbers<E, Idl>(
          "omega_n", [](const E& e) { return e.omega_n; }, [](Idl& o, const auto& v) { o.omega_n(v); }),
      per_blade_numbers<E, Idl>(
          "zeta", [](const E& e) { return e.zeta; }, [](Idl& o, const auto& v) { o.zeta(v); }),
      per_blade_field<E, Idl>(
          "class", [](const E& e) { return e.fault_class; },
          [](Idl& o, const auto& v) {
            for (int i = 0; i < kBlades; ++i) o.fault_class()[i] = idl_class(v[i]);
          },
          [](const std::string& c) { return c; }),
      per_blade_numbers<E, Idl>(
          "alpha", [](const E& e) { return e.alpha; }, [](Idl& o, const auto& v) { o.alpha(v); }),
      per_blade_field<E, Idl>(
          "excited", [](const E& e) { return e.excited; }, [](Idl& o, const auto& v) { o.excited(v); },
          [](bool x) { return std::string(x ? "1" : "0"); }),
  };
  s.configure = [config](const YamlSection& cfg) {
    *config = load_pitch_diag_config(cfg, configured_turbine(cfg));
  };
  s.make = [config](const std::string&) { return std::make_unique<PitchDiagnoser>(*config); };
  return service_spec(std::move(s));
}

}  // namespace windfdi::pitch_diag
