// windfdi-ice-detect's service spec: per-turbine IceDetector, aerodynamic power from the model or the
// recording.
#include "ice_service.hpp"

#include <cmath>
#include <memory>

#include "Estimates.h"
#include "csv.hpp"
#include "dds/endpoints.hpp"
#include "deploy_dir.hpp"

namespace windfdi::ice_detect {

namespace {

class IceDiagnoser : public TurbineDiagnoser {
 public:
  IceDiagnoser(const DetectorConfig& c, const TurbineParams& p, const AeroModel& aero)
      : detector_(c, p), aero_power_(aero, c.wind_window, c.estimator.sample_time) {}
  bool update(const FrameSample& s, bool gap, std::vector<FaultEvent>& events) override {
    FrameSample centre;
    bool centre_gap = false;
    double power = kNaN;
    if (!aero_power_.push(s, gap, centre, centre_gap, power)) return true;  // judged half a window later
    return detector_.update(centre, power, centre_gap, events);
  }
  void set_context(const InputContext& context, double) override { detector_.set_context(context); }
  bool estimate_due(std::vector<std::string>& values) override {
    if (!detector_.estimate_due(last_)) return false;
    values = {format_number(last_.inertia), format_number(last_.ice_mass), last_.excited ? "1" : "0"};
    return true;
  }
  const InertiaOutput& last() const { return last_; }

 private:
  IceDetector detector_;
  AeroPowerInput aero_power_;
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
  spec.configure = [state](const YamlSection& cfg) {
    state->turbine = configured_turbine(cfg);
    state->config = load_detector_config(cfg, state->turbine);
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
