// windfdi-plant's runner.
#include "plant_node.hpp"

#include <spdlog/spdlog.h>

#include <cmath>
#include <cstdlib>
#include <map>
#include <memory>

#include "ControlConfiguration.h"
#include "LidarFrame.h"
#include "TurbineFrame.h"
#include "configuration_lease.hpp"
#include "dds/convert.hpp"
#include "dds/endpoints.hpp"
#include "deploy_dir.hpp"
#include "health.hpp"
#include "hop_trace.hpp"
#include "replay_csv.hpp"
#include "sensor_bias_estimate_topic.hpp"
#include "turbine_selection.hpp"
#include "turbine_sim.hpp"

namespace windfdi::plant {

std::vector<std::pair<double, double>> parse_clock_steps(const std::vector<std::string>& values) {
  std::vector<std::pair<double, double>> steps;
  for (const auto& v : values) {
    const auto colon = v.find(':');
    char* end = nullptr;
    const double at = colon == std::string::npos ? kNaN : std::strtod(v.c_str(), &end);
    const bool at_ok =
        colon != std::string::npos && end == v.c_str() + colon && std::isfinite(at) && at >= 0.0;
    const double seconds = at_ok ? std::strtod(v.c_str() + colon + 1, &end) : kNaN;
    if (!at_ok || colon + 1 == v.size() || *end != '\0' || !std::isfinite(seconds))
      throw ConfigError("--clock-step", 0, v,
                        "want AT:SECONDS, e.g. 120:-300 (simulated s, then the step in s)");
    steps.emplace_back(at, seconds);
  }
  return steps;
}

double parse_rate(const std::string& text) {
  if (text == "realtime") return 1.0;
  if (text == "max") return 0.0;
  char* end = nullptr;
  const double f = std::strtod(text.c_str(), &end);
  if (end == text.c_str() || *end != '\0' || !(f > 0.0) || !std::isfinite(f))
    throw ConfigError("--rate", 0, "", "'" + text + "' is not realtime, max or a positive factor");
  return f;
}

namespace {

// The DDS side: frames and LIDAR out, configurations and corrected measurements in.
struct Bus {
  Bus(const CommonOptions& common, const std::vector<std::string>& ids, int block, double rate, double dt)
      : participant(participant_options(common, "windfdi-plant")),
        frames(participant, "sensor_stream",
               [&](eprosima::fastdds::dds::DataWriterQos& q) {
                 // Deadline: two block periods of wall time; none when running as fast as possible.
                 if (rate > 0.0) {
                   const double period = 2.0 * block * dt / rate;
                   q.deadline().period = eprosima::fastrtps::Duration_t(std::max(period, 0.02));
                 } else {
                   q.deadline().period = eprosima::fastrtps::c_TimeInfinite;
                 }
               }),
        lidar(participant),
        configs(participant, ids, &wakeup),
        // The newest corrected speed is all the controller takes, at its next step: no wake-up per estimate
        // and no reliable bookkeeping for 100 estimates a second per turbine (estimate_newest).
        bias(participant, ids, nullptr, "estimate_newest"),
        health(participant, "plant", ids) {}
  bus::Participant participant;
  bus::Wakeup wakeup;
  bus::Writer<windfdi::TurbineFrame> frames;
  bus::Writer<windfdi::LidarFrame> lidar;
  bus::Reader<windfdi::ControlConfiguration> configs;
  bus::Reader<windfdi::SensorBiasEstimate> bias;
  HealthReporter health;
  HopTrace trace{"plant"};
};

struct TurbineRun {
  explicit TurbineRun(double lease) : control(lease) {}
  std::unique_ptr<TurbineSim> sim;
  windfdi::TurbineFrame frame;
  ConfigurationLease control;
  uint64_t config_revision = 0;
  std::string arbiter;
  eprosima::fastrtps::rtps::InstanceHandle_t config_writer;  // of the applied configuration
  uint64_t lidar_sequence = 0;
  std::vector<int> fault_column;  // per own fault: index into the recording's fault columns
};

ControlInput to_input(const windfdi::ControlConfiguration& c) {
  ControlSettings s;
  s.mode = bus::from_idl(c.mode());
  s.ipc_source = bus::from_idl(c.ipc_source());
  s.ice_mode = bus::from_idl(c.ice_mode());
  for (std::size_t i = 0; i < 3; ++i) s.pitch_rate_limit[i] = c.pitch_rate_limit()[i];
  s.use_corrected_generator_speed = c.use_corrected_generator_speed();
  s.inertia = c.inertia();
  s.torque_compensation = c.torque_compensation();
  return control_input(s);
}

}  // namespace

int run_plant(const CommonOptions& common, const PlantOptions& o) {
  Scenario sc = load_scenario(o.scenario, deploy_dir());
  if (o.duration >= 0.0) sc.duration = o.duration;
  if (o.block < 1 || o.block > 32) throw ConfigError("--block", 0, "", "must be 1..32");
  const double dt = 1.0 / sc.sample_rate;
  const TurbineSelection selection(common.turbines);
  std::vector<std::string> ids;
  std::map<std::string, TurbineRun> runs;
  std::vector<std::string> fault_columns;
  for (const auto& t : sc.turbines) {
    if (!selection.contains(t.id)) continue;
    ids.push_back(t.id);
    auto& run = runs.try_emplace(t.id, o.config_lease).first->second;
    const auto faults = sc.faults_of(t.id);
    run.sim = std::make_unique<TurbineSim>(sc.turbine, t, faults, sc.seed, sc.sample_rate);
    run.frame.turbine_id(t.id);
    for (const auto& f : faults) {
      const std::string name = "fault_active_" + f.target + "_" + f.type;
      auto it = std::find(fault_columns.begin(), fault_columns.end(), name);
      if (it == fault_columns.end()) it = fault_columns.insert(fault_columns.end(), name);
      run.fault_column.push_back(static_cast<int>(it - fault_columns.begin()));
    }
  }
  if (ids.empty())
    throw ConfigError(o.scenario, 0, "turbines", "no turbine of the scenario matches --turbine");
  if (o.offline && o.record.empty()) spdlog::warn("--offline without --record: the simulation goes nowhere");

  std::vector<std::string> extra;
  std::size_t n_truth = 0;
  if (o.record_truth) {
    extra = runs.begin()->second.sim->truth_columns();
    extra.resize(extra.size() - runs.begin()->second.fault_column.size());  // per-turbine fault columns below
    n_truth = extra.size();
    extra.insert(extra.end(), fault_columns.begin(), fault_columns.end());
  }
  std::unique_ptr<FrameCsvWriter> recorder;
  if (!o.record.empty()) recorder = std::make_unique<FrameCsvWriter>(o.record, extra);
  std::unique_ptr<Bus> dds;
  if (!o.offline) dds = std::make_unique<Bus>(common, ids, o.block, o.rate, dt);

  spdlog::info("plant: {} turbine(s), {:.0f} s at {} Hz, rate {}, scenario {}", ids.size(), sc.duration,
               sc.sample_rate, o.rate > 0 ? std::to_string(o.rate) + "x" : std::string("max"), sc.file);
  const uint64_t n_samples = static_cast<uint64_t>(std::llround(sc.duration * sc.sample_rate));
  const double wall_start = wall_time();
  double last_progress = wall_start;
  std::vector<double> values;
  std::vector<windfdi::ControlConfiguration> configs;
  std::vector<bus::SampleMeta> config_meta;
  std::vector<windfdi::SensorBiasEstimate> biases;
  uint64_t write_failures = 0;
  for (uint64_t k = 0; k < n_samples && !shutdown_requested(); ++k) {
    const double t = static_cast<double>(k) * dt;
    if (o.rate > 0.0) {
      const double due = wall_start + t / o.rate;
      const double now = wall_time();
      if (due > now)
        sleep_unless_shutdown(
            std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::duration<double>(due - now)));
    }
    const double now = wall_time();
    if (dds) {
      configs.clear();
      config_meta.clear();
      dds->configs.take(configs, &config_meta);
      for (std::size_t i = 0; i < configs.size(); ++i) {
        const auto& c = configs[i];
        auto it = runs.find(c.turbine_id());
        if (it == runs.end()) continue;
        TurbineRun& r = it->second;
        r.config_writer = config_meta[i].writer;
        // The configuration acts from this control step on (r.sim->step below).
        if (dds->trace.on() && c.revision() != r.config_revision) {
          const std::string key = std::to_string(c.revision());
          dds->trace.record("config_receive", c.turbine_id(), key, config_meta[i].reception_time);
          dds->trace.record("config_apply", c.turbine_id(), key, wall_time());
        }
        if (c.revision() != r.config_revision || c.arbiter_id() != r.arbiter)
          spdlog::info("{}: applying configuration r{} from {}: mode {}, ipc {}", c.turbine_id(),
                       c.revision(), c.arbiter_id(), static_cast<int>(c.mode()),
                       static_cast<int>(c.ipc_source()));
        r.control.received(to_input(c), now);
        r.config_revision = c.revision();
        r.arbiter = c.arbiter_id();
      }
      for (const auto& ev : dds->configs.take_liveliness_events())
        for (auto& [id, r] : runs)
          if (r.config_writer == ev.writer) r.control.writer_liveliness(ev.alive);
      biases.clear();
      dds->bias.take(biases);
      for (const auto& b : biases) {
        auto it = runs.find(b.turbine_id());
        if (it == runs.end()) continue;
        it->second.control.corrected_generator_speed(b.corrected_generator_speed(), now);
      }
    }
    for (const auto& id : ids) {
      TurbineRun& r = runs.at(id);
      bool expired = false;
      const ControlInput in = r.control.input(now, &expired);
      if (expired)
        spdlog::warn("{}: no configuration for {:.1f} s (arbiter lost): back to defaults{}", id,
                     r.control.lease(), r.control.stopped() ? ", staying in safe stop" : "");
      FrameSample s = r.sim->step(in);
      if (!o.record_truth) s.aero_torque = s.aero_power = kNaN;  // not measured on a real turbine
      const double simulated = s.t;
      for (const auto& [at, seconds] : o.clock_steps)
        if (simulated >= at) s.t += seconds;
      if (recorder) {
        values.clear();
        if (o.record_truth) {
          const auto tv = r.sim->truth_values();
          values.assign(tv.begin(), tv.begin() + static_cast<long>(n_truth));
          values.resize(extra.size(), 0.0);
          const auto active = r.sim->faults_active();
          for (std::size_t i = 0; i < active.size(); ++i)
            values[n_truth + r.fault_column[i]] = active[i] ? 1.0 : 0.0;
        }
        recorder->write(id, s, values);
      }
      if (!dds) continue;
      r.frame.samples().push_back(bus::to_idl(s));
      if (static_cast<int>(r.frame.samples().size()) >= o.block) {
        r.frame.t(s.t);
        if (!dds->frames.write(r.frame)) ++write_failures;
        r.frame.samples().clear();
      }
      if (r.sim->lidar_updated()) {
        windfdi::LidarFrame l;
        l.t(s.t);
        l.turbine_id(id);
        l.sequence(r.lidar_sequence++);
        l.v_upper(s.lidar_v_upper);
        l.v_lower(s.lidar_v_lower);
        l.distance(r.sim->lidar_distance());
        l.valid_mask((std::isfinite(s.lidar_v_upper) ? 1u : 0u) | (std::isfinite(s.lidar_v_lower) ? 2u : 0u));
        if (!dds->lidar.write(l)) ++write_failures;
      }
      dds->health.count_in(id);
    }
    if (dds) {
      dds->health.set_state(windfdi::SERVICE_OK);
      dds->health.set_streams_of(dds->frames, dds->lidar, dds->configs, dds->bias);
      dds->health.tick(now);
    }
    if (o.progress_period > 0 && now - last_progress >= o.progress_period) {
      last_progress = now;
      spdlog::info("plant: t = {:.0f} / {:.0f} s ({:.0f}x real time){}", t, sc.duration,
                   t / (now - wall_start),
                   write_failures ? fmt::format(", {} DDS writes refused", write_failures) : "");
    }
  }
  if (recorder) recorder->flush();
  if (dds) dds->frames.get()->wait_for_acknowledgments(eprosima::fastrtps::Duration_t(2, 0));
  spdlog::info("plant: done at t = {:.2f} s after {:.1f} s wall{}", runs.begin()->second.sim->time(),
               wall_time() - wall_start,
               write_failures ? fmt::format(", {} DDS writes refused", write_failures) : "");
  return write_failures ? kExitFailure : kExitOk;
}

}  // namespace windfdi::plant
