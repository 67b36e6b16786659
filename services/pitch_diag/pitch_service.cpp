// windfdi-pitch-diag's service spec: one PitchDiagnoser per turbine, 10 Hz PitchActuatorEstimate.
#include "pitch_service.hpp"

#include <memory>

#include "Estimates.h"
#include "csv.hpp"
#include "dds/convert.hpp"
#include "dds/endpoints.hpp"

namespace windfdi::pitch_diag {

FaultEvent to_fault_event(const PitchEvent& e) {
  FaultEvent f;
  f.t = e.t;
  f.component = e.component;
  f.fault = e.fault;
  f.raised = e.raised;
  f.severity = e.severity;
  f.t_detected = e.t_detected;
  f.statistic = e.statistic;
  f.threshold = e.threshold;
  f.size = e.size;
  f.detail = e.detail;
  return f;
}

namespace {

class PitchTurbine : public TurbineDiagnoser {
 public:
  explicit PitchTurbine(const PitchDiagConfig& c) : diagnoser_(c) {}
  bool update(const FrameSample& s, bool gap, std::vector<FaultEvent>& events) override {
    // A gap is seen by the core through the sequence number; `gap` only repeats it.
    (void)gap;
    const uint64_t rejected_before = diagnoser_.rejected();
    pitch_events_.clear();
    diagnoser_.update(s, pitch_events_);
    for (const auto& e : pitch_events_) events.push_back(to_fault_event(e));
    return diagnoser_.rejected() == rejected_before;
  }
  bool estimate_due(std::vector<std::string>& values) override {
    if (!diagnoser_.estimate_due(last_)) return false;
    values.clear();
    for (double w : last_.omega_n) values.push_back(format_number(w));
    for (double z : last_.zeta) values.push_back(format_number(z));
    for (const auto& c : last_.fault_class) values.push_back(c);
    for (double a : last_.alpha) values.push_back(format_number(a));
    for (bool x : last_.excited) values.push_back(x ? "1" : "0");
    return true;
  }
  void set_context(const InputContext& context, double t) override { diagnoser_.set_context(context, t); }
  const PitchEstimate& last() const { return last_; }

 private:
  PitchDiagnoser diagnoser_;
  std::vector<PitchEvent> pitch_events_;
  PitchEstimate last_;
};

}  // namespace

ServiceSpec pitch_diag_spec() {
  auto config = std::make_shared<PitchDiagConfig>();
  ServiceSpec spec;
  spec.name = "pitch_diag";
  spec.description = "Pitch-actuator fault diagnosis by model identification (Wu & Li, MIFG)";
  // The contract's columns first (omega_n, zeta, class), then the fault indicator and the excitation flag.
  spec.estimate_columns = {"omega_n_1", "omega_n_2", "omega_n_3", "zeta_1",    "zeta_2",
                           "zeta_3",    "class_1",   "class_2",   "class_3",   "alpha_1",
                           "alpha_2",   "alpha_3",   "excited_1", "excited_2", "excited_3"};
  spec.configure = [config](const YamlSection& cfg) { *config = load_pitch_diag_config(cfg); };
  spec.make = [config](const std::string&) -> std::unique_ptr<TurbineDiagnoser> {
    return std::make_unique<PitchTurbine>(*config);
  };
  spec.make_publisher = [](bus::Participant& participant) -> EstimatePublisher {
    auto writer = std::make_shared<bus::Writer<windfdi::PitchActuatorEstimate>>(participant);
    return [writer](const std::string& id, double, TurbineDiagnoser& d) {
      const PitchEstimate& o = static_cast<PitchTurbine&>(d).last();
      windfdi::PitchActuatorEstimate e;
      e.t(o.t);
      e.turbine_id(id);
      for (int i = 0; i < kBlades; ++i) {
        e.omega_n()[i] = o.omega_n[i];
        e.zeta()[i] = o.zeta[i];
        e.alpha()[i] = o.alpha[i];
        windfdi::FaultClass c = windfdi::FAULT_NONE;
        bus::fault_class_from_name(o.fault_class[i], c);
        e.fault_class()[i] = c;
        e.excited()[i] = o.excited[i];
      }
      writer->write(e);
    };
  };
  return spec;
}

}  // namespace windfdi::pitch_diag
