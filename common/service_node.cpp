// The DDS side every diagnostic service shares.
#include "service_node.hpp"

#include <spdlog/spdlog.h>

#include <cmath>

#include "dds/convert.hpp"

namespace windfdi {

DiagnosticNode::DiagnosticNode(const CommonOptions& options, const std::string& service)
    : service_(service),
      turbines_(options.turbines),
      participant_(participant_options(options, "windfdi-" + service)),
      frames_(participant_, options.turbines, &wakeup_),
      faults_(participant_),
      health_(participant_, service, options.turbines),
      other_faults_(participant_, options.turbines, &wakeup_),
      configurations_(participant_, options.turbines, &wakeup_),
      limit_(options.max_turbines, service),
      trace_(service) {}

const InputContext& DiagnosticNode::context(const std::string& turbine_id) {
  return contexts_.try_emplace(turbine_id, service_).first->second.context();
}

void DiagnosticNode::take_context() {
  std::vector<windfdi::FaultReport> reports;
  other_faults_.take(reports);
  for (const auto& r : reports) {
    // Checked before the turbine is admitted: a foreign report takes no place among the turbines followed.
    const FaultEvent e = bus::to_event(r);
    if (foreign_reports_.refuse(e) || !limit_.admit(r.turbine_id())) continue;
    auto& tracker = contexts_.try_emplace(r.turbine_id(), service_).first->second;
    if (tracker.on_fault(e))
      spdlog::info("{}: {} {} {} by {}: inputs that rely on it are suspect", r.turbine_id(), r.component(),
                   bus::fault_class_name(r.fault_class()),
                   r.state() == windfdi::FAULT_STATE_RAISED ? "raised" : "cleared", r.source());
  }
  std::vector<windfdi::ControlConfiguration> configs;
  configurations_.take(configs);
  for (const auto& c : configs) {
    if (!limit_.admit(c.turbine_id())) continue;
    // The control content only: a republished configuration, or new reasons alone, moves nothing.
    std::string content = std::to_string(c.mode()) + "/" + std::to_string(c.ipc_source()) + "/" +
                          std::to_string(c.use_corrected_rotor_speed()) +
                          std::to_string(c.use_corrected_generator_speed()) + "/" +
                          std::to_string(c.ice_mode());
    for (int i = 0; i < 3; ++i)
      content += "/" + std::to_string(c.use_corrected_pitch()[i]) + std::to_string(c.pitch_rate_limit()[i]);
    auto& last = last_control_[c.turbine_id()];
    const bool stopped = c.mode() == windfdi::MODE_SAFE_STOP;
    const std::array<double, 3> rates{c.pitch_rate_limit()[0], c.pitch_rate_limit()[1],
                                      c.pitch_rate_limit()[2]};
    // Also the first configuration seen (a service restarted on a stopped or derated turbine).
    if (last != content) {
      contexts_.try_emplace(c.turbine_id(), service_).first->second.on_reconfiguration(stopped, rates);
      spdlog::info("{}: configuration r{} of t {:.2f} s: {}pitch rate limits {}/{}/{} deg/s", c.turbine_id(),
                   c.revision(), c.t(), stopped ? "safe stop, " : "", rates[0], rates[1], rates[2]);
    }
    last = content;
  }
}

void DiagnosticNode::subscribe_lidar(LidarFn on_lidar) {
  on_lidar_ = std::move(on_lidar);
  lidar_ = std::make_unique<bus::Reader<windfdi::LidarFrame>>(participant_, turbines_, &wakeup_);
}

void DiagnosticNode::publish(const FaultEvent& e) {
  if (trace_.on()) {
    const std::string key = HopTrace::report_key(e.component, e.fault, e.t);
    trace_.record("frame_write", e.turbine_id, key, frame_meta_.source_time);
    trace_.record("frame_receive", e.turbine_id, key, frame_meta_.reception_time);
    trace_.record("frame_wake", e.turbine_id, key, frame_woke_);
    trace_.record("frame_take", e.turbine_id, key, frame_taken_);
    trace_.record("report_write", e.turbine_id, key, wall_time());
  }
  try {
    if (!faults_.write(bus::to_idl(e))) spdlog::error("fault report not written (DDS resource limits?)");
  } catch (const std::invalid_argument& err) {
    spdlog::error("not publishing a fault with {}: {}", err.what(), e.component);
    return;
  }
  const auto level = e.raised ? spdlog::level::warn : spdlog::level::info;
  spdlog::log(level, "{} {} {} {} ({}, statistic {:.3g}, size {:.3g}) {}", e.turbine_id, e.component, e.fault,
              e.raised ? "RAISED" : "cleared", e.severity, e.statistic, e.size, e.detail);
}

void DiagnosticNode::run(const SampleFn& process) {
  health_.set_state(windfdi::SERVICE_OK);
  std::vector<windfdi::TurbineFrame> frames;
  std::vector<bus::SampleMeta> meta;
  std::vector<windfdi::LidarFrame> lidar;
  while (!shutdown_requested()) {
    wakeup_.wait_for(std::chrono::milliseconds(100));
    const double woke = wall_time();
    take_context();
    if (lidar_) {
      lidar.clear();
      lidar_->take(lidar);
      for (const auto& f : lidar)
        if (limit_.admit(f.turbine_id())) on_lidar_(f.turbine_id(), f);
    }
    frames.clear();
    meta.clear();
    frames_.take(frames, &meta);
    const double now = wall_time();
    frame_woke_ = woke;
    frame_taken_ = now;
    for (std::size_t i = 0; i < frames.size(); ++i) {
      const std::string& id = frames[i].turbine_id();
      if (!limit_.admit(id)) continue;
      frame_meta_ = meta[i];
      auto& tracker = sequence_[id];
      auto& clock = sample_times_[id];
      // Counted into the health per frame (a string-keyed lookup per sample before).
      uint64_t in = 0, rejected = 0;
      for (const auto& s : frames[i].samples()) {
        ++in;
        // A sample without a usable time is rejected before it can count as a gap or a clock step (a peer
        // on an unsecured domain sent NaN and 1e308 times into a real turbine's stream, and blade_load
        // raised a false lidar sensor_invalid on the restarts they caused).
        if (!std::isfinite(s.t()) || std::abs(s.t()) > kMaxSampleTime) {
          ++rejected;
          continue;
        }
        const uint64_t lost = tracker.lost_before(s.sequence());
        if (lost) {
          health_.count_gap(id, lost);
          spdlog::warn("{}: {} samples lost before sequence {}; restarting history", id, lost, s.sequence());
        }
        const double step = clock.step(s.t());
        // A restarted plant also restarts its sequence (counted above); a clock step keeps it.
        if (step != 0.0 && !lost)
          spdlog::warn(
              "{}: sample time stepped by {:+.3f} s at sequence {} (controller clock stepped); restarting "
              "history",
              id, step, s.sequence());
        if (!process(id, bus::to_sample(s), lost > 0 || step != 0.0)) ++rejected;
      }
      if (in) health_.count_in(id, in);
      if (rejected) health_.count_rejected(id, rejected);
      health_.set_lag(id, std::max(0.0, now - meta[i].source_time));
    }
    // Said in the health detail (the farm shows it), at most once a second while refusals go on.
    health_.report_refusals(limit_, now);
    health_.set_streams_of(frames_, faults_, other_faults_, configurations_);
    if (lidar_) health_.add_streams(lidar_->status());
    health_.tick(now);
  }
  health_.set_state(windfdi::SERVICE_STOPPING);
  health_.tick(wall_time(), true);
}

}  // namespace windfdi
