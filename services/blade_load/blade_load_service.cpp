// windfdi-blade-load's service spec: a BladeLoadMonitor per turbine, LIDAR merged, state persisted per
// turbine.
#include "blade_load_service.hpp"

#include <spdlog/spdlog.h>

#include <memory>

#include "blade_load_estimate_topic.hpp"
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

/// The monitor with its learned state kept in a file per turbine (restored at start, saved every
/// save_period of sample time and at exit), in the shape of every service core.
class BladeLoadTurbine {
 public:
  BladeLoadTurbine(const State& s, const std::string& id)
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
  ~BladeLoadTurbine() { save(); }
  BladeLoadTurbine(const BladeLoadTurbine&) = delete;
  BladeLoadTurbine& operator=(const BladeLoadTurbine&) = delete;

  bool update(const FrameSample& s, bool gap, std::vector<FaultEvent>& events) {
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
  bool estimate_due(BladeLoadOutput& out) { return monitor_.estimate_due(out); }
  void set_context(const InputContext& context, double t) { monitor_.set_context(context, t); }

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
};

using Idl = windfdi::BladeLoadEstimate;
using E = BladeLoadOutput;

}  // namespace

ServiceSpec blade_load_spec() {
  auto state = std::make_shared<State>();
  TypedService<BladeLoadTurbine, E, Idl> s;
  s.name = "blade_load";
  s.description =
      "Blade-root moment sensor faults from the first harmonic, strain gauge vs LIDAR load model (Stotsky "
      "2014)";
  s.wants_lidar = true;
  s.inputs = {
      {"the first harmonic of each blade's root moment (the gauges against each other)",
       {"blade_moment_1", "blade_moment_2", "blade_moment_3", "azimuth", "rotor_speed"},
       true,
       "the blade-moment sensors are not diagnosed"},
      {"the LIDAR load model, a witness independent of the gauges",
       {"lidar_v_upper", "lidar_v_lower", "pitch_1", "pitch_2", "pitch_3"},
       false,
       "detection relies on the blade-vs-blade channels (a fault common to every gauge goes unseen)"},
  };
  // The replay contract's columns first (a1_sensor, a1_model, delta_a), then the validity flags.
  s.fields = {
      per_blade_numbers<E, Idl>(
          "a1_sensor", [](const E& e) { return e.a1_sensor; }, [](Idl& o, const auto& v) { o.a1_sensor(v); }),
      per_blade_numbers<E, Idl>(
          "a1_model", [](const E& e) { return e.a1_model; }, [](Idl& o, const auto& v) { o.a1_model(v); }),
      per_blade_numbers<E, Idl>(
          "delta_a", [](const E& e) { return e.delta_a; }, [](Idl& o, const auto& v) { o.delta_a(v); }),
      per_blade_field<E, Idl>(
          "valid", [](const E& e) { return e.valid; }, [](Idl& o, const auto& v) { o.valid(v); },
          [](bool x) { return std::string(x ? "1" : "0"); }),
      flag_field<E, Idl>(
          "lidar_ok", [](const E& e) { return e.lidar_ok; }, [](Idl& o, bool v) { o.lidar_ok(v); }),
  };
  s.configure = [state](const YamlSection& cfg) {
    // Relative files are taken beside the configuration file.
    state->turbine = configured_turbine(cfg);
    state->config = load_monitor_config(cfg, state->turbine);
    // A table of the turbine's own model unless a (measured) table is given: a table made for another rotor
    // reads every blade's load wrong by the ratio of the two rotors' moments.
    const std::string table_file = cfg.get<std::string>("load_table_file", "");
    state->table = table_file.empty() ? LoadTable::from_turbine(state->turbine)
                                      : LoadTable::load_csv(cfg.get_path("load_table_file", ""));
    // "" (the default) keeps no state.
    state->state_file = cfg.get<std::string>("state_file", "").empty() ? "" : cfg.get_path("state_file", "");
    state->save_period = cfg.get_number("save_period", 600.0, 1.0, 1e7);
  };
  s.make = [state](const std::string& id) { return std::make_unique<BladeLoadTurbine>(*state, id); };
  return service_spec(std::move(s));
}

}  // namespace windfdi::blade_load
