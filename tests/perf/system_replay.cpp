// The whole diagnosis in one process: the four services' cores fed sample by sample, each fault event handed
// at once to the other services' input context and to the arbiter's decision (isolation included), the
// history written as `windfdi-farm history --json` lines for `windfdi-farm report --history`. On a recording
// it is open loop (the arbiter's configurations do not reach the recorded plant); with --scenario the plant
// runs here and follows the arbiter as windfdi-plant does (mode, IPC source, pitch rate limits, the corrected
// generator speed, the ice-adapted inertia): without that a stuck generator-speed reading stalls the rotor
// and hides every later fault. A fast way to tune and judge the services together; the DDS system is judged
// by multi_fault_suite.py.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>

#include "blade_load_service.hpp"
#include "configuration_lease.hpp"
#include "decision.hpp"
#include "deploy_dir.hpp"
#include "drive_train_service.hpp"
#include "ice_service.hpp"
#include "input_context.hpp"
#include "pitch_service.hpp"
#include "replay.hpp"
#include "replay_csv.hpp"
#include "scenario.hpp"
#include "sensor_bias_service.hpp"
#include "turbine_sim.hpp"

using namespace windfdi;

namespace {

struct Service {
  ServiceSpec spec;
  std::map<std::string, std::unique_ptr<TurbineDiagnoser>> turbines;
  std::map<std::string, InputContextTracker> contexts;
  std::map<std::string, InputContext> given;
  std::unique_ptr<ReplaySink>
      estimates;  // --estimates: this service's estimates, as its own replay writes them
};

struct Turbine {
  arbiter::Arbiter arbiter;
  arbiter::Configuration last;
  bool have_last = false;
  double next_evaluation = 0.0;
  // What the plant applies, by the plant's own rule (the in-process arbiter never falls silent: no lease).
  plant::ConfigurationLease control{std::numeric_limits<double>::infinity()};
};

/// What windfdi-plant does with a configuration (the plant's own control_input rule), for the closed loop.
plant::ControlInput control_input(const arbiter::Configuration& c) {
  plant::ControlSettings s;
  s.mode = c.mode;  // one definition (common/control_modes.hpp)
  s.ipc_source = c.ipc_source;
  s.ice_mode = c.ice_mode;
  s.pitch_rate_limit = c.pitch_rate_limit;
  s.use_corrected_generator_speed = c.use_corrected_generator_speed;
  s.inertia = c.inertia;
  s.torque_compensation = c.torque_compensation;
  return plant::control_input(s);
}

/// The control content of a configuration (what DiagnosticNode compares; new reasons alone move nothing).
bool same_control(const arbiter::Configuration& a, const arbiter::Configuration& b) {
  return a.mode == b.mode && a.ipc_source == b.ipc_source &&
         a.use_corrected_rotor_speed == b.use_corrected_rotor_speed &&
         a.use_corrected_generator_speed == b.use_corrected_generator_speed && a.ice_mode == b.ice_mode &&
         a.use_corrected_pitch == b.use_corrected_pitch && a.pitch_rate_limit == b.pitch_rate_limit &&
         a.torque_compensation == b.torque_compensation;
}

int column_of(const ServiceSpec& spec, const std::string& name) {
  for (std::size_t i = 0; i < spec.estimate_columns.size(); ++i)
    if (spec.estimate_columns[i] == name) return static_cast<int>(i);
  throw ConfigError(spec.name, 0, name, "no such estimate column");
}

nlohmann::json config_json(const arbiter::Configuration& c, const std::string& id, double t) {
  nlohmann::json reasons = nlohmann::json::array();
  for (const auto& r : c.reasons)
    reasons.push_back(r.source + "/" + r.component + "/" + r.fault + ": " + r.action);
  return {{"t", t},
          {"turbine_id", id},
          {"arbiter_id", "system_replay"},
          {"mode", arbiter::to_string(c.mode)},
          {"ipc_source", arbiter::to_string(c.ipc_source)},
          {"ice_mode", arbiter::to_string(c.ice_mode)},
          {"reasons", reasons}};
}

// One --set: SERVICE.KEY=VALUE.
struct Setting {
  std::string service, key, value;
};

// Parses the --set values once; a malformed one, or one for a configuration not among `known`, is a
// ConfigError (a key the service does not know is its own check, at configure).
std::vector<Setting> parse_settings(const std::vector<std::string>& raw,
                                    const std::vector<std::string>& known) {
  std::vector<Setting> out;
  std::string names;
  for (const auto& k : known) names += (names.empty() ? "" : ", ") + k;
  for (const auto& setting : raw) {
    const auto dot = setting.find('.'), eq = setting.find('=');
    if (dot == std::string::npos || eq == std::string::npos || eq < dot)
      throw ConfigError("--set", 0, setting, "expected SERVICE.KEY=VALUE");
    Setting s{setting.substr(0, dot), setting.substr(dot + 1, eq - dot - 1), setting.substr(eq + 1)};
    if (std::find(known.begin(), known.end(), s.service) == known.end())
      throw ConfigError("--set", 0, setting, "no configuration '" + s.service + "' (" + names + ")");
    out.push_back(s);
  }
  return out;
}

// `service`'s configuration file with its --set keys replaced.
YamlSection with_settings(const std::string& file, const std::string& service,
                          const std::vector<Setting>& settings) {
  YamlSection section = YamlSection::load_file(file);
  YAML::Node node = section.node();
  for (const auto& s : settings)
    if (s.service == service) node[s.key] = YAML::Load(s.value);
  return section;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"The four services and the arbiter on one recording, in one process (open loop)"};
  std::string frames, scenario_file, history_file, config_dir = deploy_dir() + "/config";
  auto* frames_option = app.add_option("frames", frames, "recording (windfdi-plant --record): open loop");
  app.add_option("--scenario", scenario_file, "run this plant scenario here instead, closed loop")
      ->excludes(frames_option);
  app.add_option("--history", history_file, "write the history here (JSON Lines)")->required();
  app.add_option("--config-dir", config_dir, "service configurations (<service>.yaml)");
  std::string record_file, estimates_of;
  app.add_option("--estimates", estimates_of,
                 "SERVICE=FILE: write that service's estimates here (the columns of its own --replay)");
  app.add_option(
      "--record", record_file,
      "with --scenario: write the closed loop's frames here (a recording to replay one service on)");
  std::vector<std::string> settings;
  app.add_option(
      "--set", settings,
      "SERVICE.KEY=VALUE: one key of a configuration replaced (repeatable; a path as in the file, "
      "relative to --config-dir, or absolute), e.g. every service's turbine_file for another turbine");
  CLI11_PARSE(app, argc, argv);
  try {
    std::vector<Service> services;
    for (auto make : {blade_load::blade_load_spec, sensor_bias::sensor_bias_spec, pitch_diag::pitch_diag_spec,
                      ice_detect::ice_detect_spec, drive_train::drive_train_spec})
      services.push_back(Service{make(), {}, {}, {}, nullptr});
    std::vector<std::string> known{"arbiter"};
    for (const auto& s : services) known.push_back(s.spec.name);
    const std::vector<Setting> set = parse_settings(settings, known);
    if (!estimates_of.empty()) {
      const auto eq = estimates_of.find('=');
      auto it = std::find_if(services.begin(), services.end(),
                             [&](const Service& s) { return s.spec.name == estimates_of.substr(0, eq); });
      if (eq == std::string::npos || it == services.end())
        throw ConfigError("--estimates", 0, estimates_of, "expected SERVICE=FILE of a diagnostic service");
      ReplayOptions options;
      options.estimates = estimates_of.substr(eq + 1);
      it->estimates = std::make_unique<ReplaySink>(options, it->spec.estimate_columns);
    }
    for (auto& s : services)
      s.spec.configure(with_settings(config_dir + "/" + s.spec.name + ".yaml", s.spec.name, set));
    const auto arbiter_config =
        arbiter::load_arbiter_config(with_settings(config_dir + "/arbiter.yaml", "arbiter", set));
    std::map<std::string, Turbine> turbines;
    std::ofstream out(history_file);
    if (!out) throw ConfigError(history_file, 0, "", "cannot write");
    auto write = [&](const char* kind, double t, const nlohmann::json& data) {
      out << nlohmann::json{{"received_at", t}, {"kind", kind}, {"data", data}}.dump() << "\n";
    };
    uint64_t events = 0;
    std::vector<FaultEvent> produced;
    // The estimates the closed loop reads: sensor_bias's corrected generator speed (the plant's controller)
    // and ice_detect's inertia (the arbiter's ice-adapted controller).
    const Service& bias = services[1];
    const Service& ice = services[3];
    const auto bias_corrected = static_cast<std::size_t>(column_of(bias.spec, "corrected_generator_speed"));
    const auto ice_inertia = static_cast<std::size_t>(column_of(ice.spec, "inertia"));
    auto process = [&](const std::string& id, const FrameSample& s, bool gap) {
      auto [tit, fresh] = turbines.try_emplace(id, Turbine{arbiter::Arbiter(arbiter_config), {}, false, s.t});
      Turbine& turbine = tit->second;
      produced.clear();
      bool ok = true;
      for (Service& svc : services) {
        auto& d = svc.turbines[id];
        if (!d) d = svc.spec.make(id);
        const InputContext& c = svc.contexts.try_emplace(id, svc.spec.name).first->second.context();
        if (!(svc.given[id] == c)) {
          svc.given[id] = c;
          d->set_context(c, s.t);
        }
        std::vector<FaultEvent> ev;
        ok &= d->update(s, gap, ev);
        std::vector<std::string> values;
        if (d->estimate_due()) {
          d->estimate_values(values);
          if (svc.estimates) svc.estimates->estimate(s.t, id, values);
          if (&svc == &bias) {
            turbine.control.corrected_generator_speed(std::stod(values.at(bias_corrected)), s.t);
          } else if (&svc == &ice) {
            const double inertia = std::stod(values.at(ice_inertia));
            if (std::isfinite(inertia) && inertia > 0) turbine.arbiter.on_inertia(inertia);
          }
        }
        for (auto& e : ev) {
          e.turbine_id = id;
          e.source = svc.spec.name;
          produced.push_back(e);
        }
      }
      for (const auto& e : produced) {
        ++events;
        write("fault", s.t, to_json(e));
        for (auto& svc : services) svc.contexts.try_emplace(id, svc.spec.name).first->second.on_fault(e);
        turbine.arbiter.on_fault(e, s.t);
      }
      if (s.t >= turbine.next_evaluation) {
        turbine.next_evaluation = s.t + 0.1;
        const auto c = turbine.arbiter.evaluate(s.t);
        if (!turbine.have_last || c != turbine.last) {
          // Every service's input context follows the arbiter's reconfigurations, as DiagnosticNode's does.
          if (!turbine.have_last || !same_control(c, turbine.last))
            for (auto& svc : services)
              svc.contexts.try_emplace(id, svc.spec.name)
                  .first->second.on_reconfiguration(c.mode == arbiter::Mode::kSafeStop, c.pitch_rate_limit);
          write("config", s.t, config_json(c, id, s.t));
          turbine.last = c;
          turbine.have_last = true;
          turbine.control.received(control_input(c), s.t);
        }
      }
      return ok;
    };
    uint64_t samples = 0;
    if (!scenario_file.empty()) {
      const plant::Scenario sc = plant::load_scenario(scenario_file, deploy_dir());
      std::vector<std::unique_ptr<plant::TurbineSim>> sims;
      for (const auto& t : sc.turbines)
        sims.push_back(
            std::make_unique<plant::TurbineSim>(sc.turbine, t, sc.faults_of(t.id), sc.seed, sc.sample_rate));
      const auto n = static_cast<uint64_t>(std::llround(sc.duration * sc.sample_rate));
      std::unique_ptr<FrameCsvWriter> recorder;
      if (!record_file.empty()) recorder = std::make_unique<FrameCsvWriter>(record_file);
      for (uint64_t k = 0; k < n; ++k)
        for (auto& sim : sims) {
          auto it = turbines.find(sim->id());
          const plant::ControlInput in =
              it == turbines.end() ? plant::ControlInput{} : it->second.control.input(sim->time());
          FrameSample s = sim->step(in);
          // Not measured on a real turbine (windfdi-plant records them only as truth).
          s.aero_torque = s.aero_power = kNaN;
          if (recorder) recorder->write(sim->id(), s, {});
          process(sim->id(), s, false);
          ++samples;
        }
    } else {
      if (frames.empty()) throw ConfigError("system_replay", 0, "frames", "give a recording or --scenario");
      ReplayOptions options;
      options.frames = frames;
      samples =
          run_replay(options, {}, [&](const std::string& id, const FrameSample& s, bool gap, ReplaySink&) {
            return process(id, s, gap);
          }).samples;
    }
    std::cerr << "system_replay: " << samples << " samples, " << events << " fault events\n";
  } catch (const ConfigError& e) {
    std::cerr << "system_replay: " << e.what() << "\n";
    return 2;
  }
  return 0;
}
