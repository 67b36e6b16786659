// windfdi-blade-load's service spec: a BladeLoadMonitor per turbine, LIDAR merged, state persisted per
// turbine.
#include "blade_load_service.hpp"

#include <spdlog/spdlog.h>

#include <memory>

#include "Estimates.h"
#include "csv.hpp"
#include "dds/endpoints.hpp"
#include "deploy_dir.hpp"

namespace windfdi::blade_load {

std::string state_path_for(const std::string& pattern, const std::string& id) {
  std::string s = pattern;
  for (std::size_t p = s.find("{turbine}"); p != std::string::npos; p = s.find("{turbine}", p + id.size()))
    s.replace(p, 9, id);
  return s;
}

namespace {

struct State {
  TurbineParams turbine;
  MonitorConfig config;
  LoadTable table;
  std::string state_file;
  double save_period = 600.0;
};

class BladeLoadDiagnoser : public TurbineDiagnoser {
 public:
  BladeLoadDiagnoser(const State& s, const std::string& id)
      : monitor_(s.config, s.table),
        path_(s.state_file.empty() ? "" : state_path_for(s.state_file, id)),
        save_period_(s.save_period) {
    if (path_.empty()) return;
    MonitorState st;
    if (load_state(path_, st)) {
      monitor_.restore(st);
      spdlog::info("blade_load {}: restored learned table and healthy statistics from {}", id, path_);
    }
  }
  ~BladeLoadDiagnoser() override { save(); }
  bool update(const FrameSample& s, bool gap, std::vector<FaultEvent>& events) override {
    const bool ok = monitor_.update(s, gap, events);
    if (!path_.empty() && ok) {
      if (next_save_ < 0) next_save_ = s.t + save_period_;
      if (s.t >= next_save_) {
        save();
        next_save_ = s.t + save_period_;
      }
    }
    return ok;
  }
  void set_context(const InputContext& context, double t) override { monitor_.set_context(context, t); }
  bool estimate_due(std::vector<std::string>& values) override {
    if (!monitor_.estimate_due(last_)) return false;
    values.clear();
    for (double v : last_.a1_sensor) values.push_back(format_number(v));
    for (double v : last_.a1_model) values.push_back(format_number(v));
    for (double v : last_.delta_a) values.push_back(format_number(v));
    return true;
  }
  const BladeLoadOutput& last() const { return last_; }

 private:
  void save() {
    if (path_.empty()) return;
    try {
      save_state(monitor_.state(), path_);
    } catch (const std::exception& e) {
      spdlog::error("blade_load: cannot save state: {}", e.what());
    }
  }
  BladeLoadMonitor monitor_;
  std::string path_;
  double save_period_;
  double next_save_ = -1.0;
  BladeLoadOutput last_;
};

}  // namespace

ServiceSpec blade_load_spec() {
  auto state = std::make_shared<State>();
  ServiceSpec spec;
  spec.name = "blade_load";
  spec.description =
      "Blade-root moment sensor faults from the first harmonic, strain gauge vs LIDAR load model (Stotsky "
      "2014)";
  spec.estimate_columns = {"a1_sensor_1", "a1_sensor_2", "a1_sensor_3", "a1_model_1", "a1_model_2",
                           "a1_model_3",  "delta_a_1",   "delta_a_2",   "delta_a_3"};
  spec.wants_lidar = true;
  spec.configure = [state](const YamlSection& cfg) {
    // Relative files are taken beside the configuration file.
    state->turbine = configured_turbine(cfg);
    state->config = load_monitor_config(cfg, state->turbine);
    state->table = LoadTable::load_csv(
        cfg.get_path("load_table_file", deploy_dir() + "/turbine/benchmark_4.8MW_load_table.csv"));
    // "" (the default) keeps no state.
    state->state_file = cfg.get<std::string>("state_file", "").empty() ? "" : cfg.get_path("state_file", "");
    state->save_period = cfg.get_number("save_period", 600.0, 1.0, 1e7);
  };
  spec.make = [state](const std::string& id) -> std::unique_ptr<TurbineDiagnoser> {
    return std::make_unique<BladeLoadDiagnoser>(*state, id);
  };
  spec.make_publisher = [](bus::Participant& participant) -> EstimatePublisher {
    auto writer = std::make_shared<bus::Writer<windfdi::BladeLoadEstimate>>(participant);
    return [writer](const std::string& id, double, TurbineDiagnoser& d) {
      const auto& o = static_cast<BladeLoadDiagnoser&>(d).last();
      windfdi::BladeLoadEstimate e;
      e.t(o.t);
      e.turbine_id(id);
      e.a1_sensor(o.a1_sensor);
      e.a1_model(o.a1_model);
      e.delta_a(o.delta_a);
      e.valid(o.valid);
      e.lidar_ok(o.lidar_ok);
      writer->write(e);
    };
  };
  return spec;
}

}  // namespace windfdi::blade_load
