// The whole diagnosis of a recording in one process: the four services' cores fed sample by sample, each
// fault event handed at once to the other services' input context and to the arbiter's decision (isolation
// included), the history written as `windfdi-farm history --json` lines for `windfdi-farm report --history`.
// Open loop (the arbiter's configurations do not reach the recorded plant): a fast way to tune and judge
// the services together; the DDS system itself is judged by multi_fault_suite.sh.
#include <CLI/CLI.hpp>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>

#include "blade_load_service.hpp"
#include "decision.hpp"
#include "deploy_dir.hpp"
#include "ice_service.hpp"
#include "input_context.hpp"
#include "pitch_service.hpp"
#include "replay.hpp"
#include "sensor_bias_service.hpp"

using namespace windfdi;

namespace {

struct Service {
  ServiceSpec spec;
  std::map<std::string, std::unique_ptr<TurbineDiagnoser>> turbines;
  std::map<std::string, InputContextTracker> contexts;
  std::map<std::string, InputContext> given;
};

struct Turbine {
  arbiter::Arbiter arbiter;
  arbiter::Configuration last;
  bool have_last = false;
  double next_evaluation = 0.0;
};

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

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"The four services and the arbiter on one recording, in one process (open loop)"};
  std::string frames, history_file, config_dir = deploy_dir() + "/config";
  app.add_option("frames", frames, "recording (windfdi-plant --record)")->required();
  app.add_option("--history", history_file, "write the history here (JSON Lines)")->required();
  app.add_option("--config-dir", config_dir, "service configurations (<service>.yaml)");
  CLI11_PARSE(app, argc, argv);
  try {
    std::vector<Service> services;
    for (auto make : {blade_load::blade_load_spec, sensor_bias::sensor_bias_spec, pitch_diag::pitch_diag_spec,
                      ice_detect::ice_detect_spec}) {
      Service s{make(), {}, {}, {}};
      s.spec.configure(YamlSection::load_file(config_dir + "/" + s.spec.name + ".yaml"));
      services.push_back(std::move(s));
    }
    const auto arbiter_config =
        arbiter::load_arbiter_config(YamlSection::load_file(config_dir + "/arbiter.yaml"));
    std::map<std::string, Turbine> turbines;
    std::ofstream out(history_file);
    if (!out) throw ConfigError(history_file, 0, "", "cannot write");
    auto write = [&](const char* kind, double t, const nlohmann::json& data) {
      out << nlohmann::json{{"received_at", t}, {"kind", kind}, {"data", data}}.dump() << "\n";
    };
    uint64_t events = 0;
    std::vector<FaultEvent> produced;
    ReplayOptions options;
    options.frames = frames;
    const auto stats =
        run_replay(options, {}, [&](const std::string& id, const FrameSample& s, bool gap, ReplaySink&) {
          auto [tit, fresh] =
              turbines.try_emplace(id, Turbine{arbiter::Arbiter(arbiter_config), {}, false, s.t});
          Turbine& turbine = tit->second;
          produced.clear();
          bool ok = true;
          for (auto& svc : services) {
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
            d->estimate_due(values);
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
              write("config", s.t, config_json(c, id, s.t));
              turbine.last = c;
              turbine.have_last = true;
            }
          }
          return ok;
        });
    std::cerr << "system_replay: " << stats.samples << " samples, " << events << " fault events\n";
  } catch (const ConfigError& e) {
    std::cerr << "system_replay: " << e.what() << "\n";
    return 2;
  }
  return 0;
}
