// The shared main of every diagnostic service.
#include "diagnostic_service.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>

#include "app.hpp"
#include "deploy_dir.hpp"
#include "lidar_frames.hpp"
#include "replay.hpp"
#include "service_node.hpp"

namespace windfdi {

namespace {

// Feeds one sample to a turbine's diagnoser and hands on what it produced, the same offline and on DDS.
// The callables are template parameters: as std::function, one was allocated per sample.
template <typename OnEvent, typename OnEstimate>
bool feed(const ServiceSpec& spec, const std::string& id, TurbineDiagnoser& d, const FrameSample& s, bool gap,
          const OnEvent& on_event, const OnEstimate& on_estimate) {
  thread_local std::vector<FaultEvent> events;
  events.clear();
  const bool ok = d.update(s, gap, events);
  for (auto& e : events) {
    e.turbine_id = id;
    e.source = spec.name;
    on_event(e);
  }
  if (d.estimate_due()) on_estimate();
  return ok;
}

// Other services' events of a replay (--context): the suspect inputs they declare, applied in sample time.
std::vector<FaultEvent> read_context_events(const std::string& file) {
  std::vector<FaultEvent> out;
  if (file.empty()) return out;
  std::ifstream in(file);
  if (!in) throw ConfigError(file, 0, "", "cannot open the --context events file");
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    try {
      out.push_back(fault_event_from_json(nlohmann::json::parse(line)));
    } catch (const std::exception& e) {
      throw ConfigError(file, n, "", std::string("not a fault event: ") + e.what());
    }
  }
  std::stable_sort(out.begin(), out.end(),
                   [](const FaultEvent& a, const FaultEvent& b) { return a.t < b.t; });
  return out;
}

int run_replay_mode(const ServiceSpec& spec, const ReplayOptions& options, const std::string& context_file) {
  std::map<std::string, std::unique_ptr<TurbineDiagnoser>> turbines;
  const auto context_events = read_context_events(context_file);
  std::size_t next_context = 0;
  std::map<std::string, InputContextTracker> contexts;
  uint32_t absent = 0;  // the recording's header lacks these channels
  const auto header = [&](const FrameCsvReader& reader) {
    const auto has = [&](const std::string& c) { return reader.has_column(c); };
    report_inputs(spec.name, spec.inputs, has, reader.path(), true);
    absent = absent_channels(has);
  };
  const auto with_absent = [&](InputContext c) {
    c.absent = absent;
    return c;
  };
  std::vector<std::string> values;  // one estimate's columns, reused
  const auto stats = run_replay(
      options, spec.estimate_columns,
      [&](const std::string& id, const FrameSample& s, bool gap, ReplaySink& sink) {
        auto& d = turbines[id];
        if (!d) {
          d = spec.make(id);
          if (absent) d->set_context(with_absent({}), s.t);
        }
        for (; next_context < context_events.size() && context_events[next_context].t <= s.t;
             ++next_context) {
          const FaultEvent& e = context_events[next_context];
          auto& tracker = contexts.try_emplace(e.turbine_id, spec.name).first->second;
          if (!tracker.on_fault(e)) continue;
          const auto it = turbines.find(e.turbine_id.empty() ? id : e.turbine_id);
          if (it != turbines.end() && it->second)
            it->second->set_context(with_absent(tracker.context()), s.t);
        }
        return feed(
            spec, id, *d, s, gap, [&](FaultEvent& e) { sink.event(e); },
            [&] {
              d->estimate_values(values);
              sink.estimate(s.t, id, values);
            });
      },
      header);
  spdlog::info(
      "replay of {}: {} samples, {} rejected, {} lost (sequence gaps), {} time steps, {} estimates, {} "
      "events",
      options.frames, stats.samples, stats.rejected, stats.sequence_gaps, stats.time_steps, stats.estimates,
      stats.events);
  return kExitOk;
}

// Samples of a turbine on DDS after which a channel never seen valid and finite counts as absent (5 s at 100
// Hz: a sensor that is merely faulty at start is invalid for longer only when it is faulty, and then
// sensor_invalid says so).
constexpr int kPresenceSamples = 500;
struct InputPresence {
  int samples = 0;
  uint32_t seen = 0, absent = 0;
};

int run_node(const ServiceSpec& spec, const CommonOptions& common) {
  DiagnosticNode node(common, spec.name);
  std::map<std::string, LidarFrames> lidar;
  if (spec.wants_lidar)
    node.subscribe_lidar([&](const std::string& id, const windfdi::LidarFrame& f) {
      if (std::isfinite(f.t()))
        lidar[id].add({f.t(), f.v_upper(), f.v_lower(), (f.valid_mask() & 3u) == 3u, f.sequence()});
    });
  const EstimatePublisher publish = spec.make_publisher ? spec.make_publisher(node.participant()) : nullptr;
  spdlog::info("{} running{}", spec.name, common.turbines.empty() ? " for every turbine" : "");
  // What the loop keeps per turbine. The samples of a frame are one turbine's, so its entry is looked up
  // when the turbine changes, not per sample (five string-keyed lookups a sample before).
  struct Turbine {
    std::unique_ptr<TurbineDiagnoser> diagnoser;
    InputPresence presence;
    InputContext given;                     // the context the diagnoser has
    const InputContext* context = nullptr;  // the node's, for this turbine
    LidarFrames* lidar = nullptr;           // once its first LIDAR frame came
  };
  std::map<std::string, Turbine> turbines;  // entries stay where they are: the pointers below hold
  std::string current_id;
  Turbine* current = nullptr;
  node.run([&](const std::string& id, const FrameSample& sample, bool gap) {
    if (!current || id != current_id) {
      current = &turbines[id];
      current_id = id;
      if (!current->diagnoser) {
        current->diagnoser = spec.make(id);
        current->context = &node.context(id);
        spdlog::info("{}: diagnosing turbine {}", spec.name, id);
      }
    }
    Turbine& turbine = *current;
    TurbineDiagnoser& d = *turbine.diagnoser;
    FrameSample s = sample;
    if (spec.wants_lidar) {
      if (!turbine.lidar) {
        const auto it = lidar.find(id);
        if (it != lidar.end()) turbine.lidar = &it->second;
      }
      const LidarFrames::Frame* l = turbine.lidar ? turbine.lidar->at(s.t) : nullptr;
      s.lidar_lost_on_the_way = turbine.lidar && turbine.lidar->take_lost();
      if (l && l->valid) {
        s.lidar_v_upper = l->v_upper;
        s.lidar_v_lower = l->v_lower;
      } else {
        s.lidar_v_upper = s.lidar_v_lower = kNaN;
        s.valid_mask &= ~kValidLidar;
      }
    }
    // What the turbine's frames carry is learnt from its first samples and said once. The LIDAR, a topic of
    // its own that may start later, is judged by its staleness instead.
    InputPresence& p = turbine.presence;
    if (p.samples < kPresenceSamples) {
      p.seen |= channels_with_values(s);
      if (++p.samples == kPresenceSamples) {
        p.absent = kValidAll & ~kValidLidar & ~p.seen;
        report_inputs(
            spec.name, spec.inputs, [&](const std::string& c) { return (p.absent & valid_bit(c)) == 0; },
            "turbine " + id, false);
      }
    }
    InputContext context = *turbine.context;
    context.absent = p.absent;
    if (!(turbine.given == context)) {
      turbine.given = context;
      d.set_context(context, s.t);
    }
    return feed(
        spec, id, d, s, gap, [&](FaultEvent& e) { node.publish(e); },
        [&] {
          if (publish) publish(id, d);
        });
  });
  return kExitOk;
}

}  // namespace

int run_diagnostic_service(int argc, char** argv, const ServiceSpec& spec) {
  const std::string exe = "windfdi-" + [&] {
    std::string n = spec.name;
    for (auto& c : n)
      if (c == '_') c = '-';
    return n;
  }();
  CLI::App app{spec.description, exe};
  CommonOptions common;
  add_common_options(app, common);
  std::string config_file;
  ReplayOptions replay;
  app.add_option("--config", config_file, "service YAML (default: built-in defaults; see deploy/config/)");
  app.add_option("--replay", replay.frames, "run offline on a recorded CSV (plain or .gz) instead of DDS");
  app.add_option("--estimates", replay.estimates, "replay: write the estimates CSV here");
  app.add_option("--events", replay.events, "replay: write the fault events (JSON Lines) here");
  std::string context_file;
  app.add_option("--context", context_file,
                 "replay: other services' fault events (JSON Lines); inputs they declare faulty are suspect");
  return run_main(app, argc, argv, common, [&] {
    spec.configure(config_file.empty() ? YamlSection(YAML::Node(YAML::NodeType::Map), "(defaults)")
                                       : YamlSection::load_file(config_file));
    if (!replay.frames.empty()) return run_replay_mode(spec, replay, context_file);
    if (!replay.estimates.empty() || !replay.events.empty() || !context_file.empty())
      throw ConfigError("--estimates/--events/--context", 0, "", "only meaningful with --replay FILE");
    return run_node(spec, common);
  });
}

}  // namespace windfdi
