// windfdi-ice-detect's service spec: per-turbine IceDetector, aerodynamic power from the model or the recording.
#include "ice_service.hpp"

#include <cmath>
#include <memory>

#include "Estimates.h"
#include "csv.hpp"
#include "dds/endpoints.hpp"

#ifndef WINDFDI_SOURCE_DEPLOY_DIR
#define WINDFDI_SOURCE_DEPLOY_DIR "/etc/windfdi"
#endif

namespace windfdi::ice_detect {

double aero_power_of(const FrameSample& s, const AeroModel& aero) {
  // The recording's column when it has one (replay contract), else the model, blade by blade: with
  // individual pitch the blades' Cp differ and Cp is far from linear in pitch.
  if (std::isfinite(s.aero_power)) return s.aero_power;
  if (!std::isfinite(s.wind_hub) || s.wind_hub < 0.0 || s.wind_hub > 60.0 || !std::isfinite(s.rotor_speed) ||
      s.rotor_speed < 0.0 || s.rotor_speed > 5.0)
    return kNaN;
  double p = 0.0;
  for (double pitch : s.pitch) {
    if (!std::isfinite(pitch) || pitch < -5.0 || pitch > 95.0) return kNaN;
    p += aero.aero_power(s.wind_hub, s.rotor_speed, pitch) / 3.0;
  }
  return p;
}

namespace {

class IceDiagnoser : public TurbineDiagnoser {
 public:
  IceDiagnoser(const DetectorConfig& c, const TurbineParams& p, const AeroModel& aero) : detector_(c, p), aero_(aero) {}
  bool update(const FrameSample& s, bool gap, std::vector<FaultEvent>& events) override {
    return detector_.update(s, aero_power_of(s, aero_), gap, events);
  }
  bool estimate_due(std::vector<std::string>& values) override {
    if (!detector_.estimate_due(last_)) return false;
    values = {format_number(last_.inertia), format_number(last_.ice_mass), last_.excited ? "1" : "0"};
    return true;
  }
  const InertiaOutput& last() const { return last_; }

 private:
  IceDetector detector_;
  const AeroModel& aero_;
  InertiaOutput last_;
};

struct State {
  TurbineParams turbine;
  DetectorConfig config;
  std::unique_ptr<AeroModel> aero;
};

}  // namespace

ServiceSpec ice_detect_spec() {
  auto state = std::make_shared<State>();
  ServiceSpec spec;
  spec.name = "ice_detect";
  spec.description = "Ice accretion and shedding from the estimated rotor inertia (Stotsky & Egardt 2013)";
  spec.estimate_columns = {"inertia", "ice_mass", "excited"};
  spec.configure = [state](const YamlSection* cfg) {
    const std::string turbine_file = std::string(WINDFDI_SOURCE_DEPLOY_DIR) + "/turbine/benchmark_4.8MW.yaml";
    state->turbine = load_turbine_params_file(cfg ? cfg->get_path("turbine_file", turbine_file) : turbine_file);
    state->config = cfg ? load_detector_config(*cfg, state->turbine)
                        : load_detector_config(YamlSection(YAML::Node(YAML::NodeType::Map), "(defaults)"), state->turbine);
    state->aero = std::make_unique<AeroModel>(state->turbine);
  };
  spec.make = [state](const std::string&) -> std::unique_ptr<TurbineDiagnoser> {
    return std::make_unique<IceDiagnoser>(state->config, state->turbine, *state->aero);
  };
  spec.make_publisher = [](bus::Participant& participant) -> EstimatePublisher {
    auto writer = std::make_shared<bus::Writer<windfdi::InertiaEstimate>>(participant);
    return [writer](const std::string& id, double, TurbineDiagnoser& d) {
      const auto& o = static_cast<IceDiagnoser&>(d).last();
      windfdi::InertiaEstimate e;
      e.t(o.t);
      e.turbine_id(id);
      e.inertia(o.inertia);
      e.inertia_clean(o.inertia_clean);
      e.ice_mass(o.ice_mass);
      e.excited(o.excited);
      writer->write(e);
    };
  };
  return spec;
}

}  // namespace windfdi::ice_detect
