// The arbiter's DDS node.
#include "arbiter_node.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>

#include "dds/convert.hpp"
#include "names.hpp"
#include "turbine_selection.hpp"

namespace windfdi::arbiter {

windfdi::ControlConfiguration to_idl(const Configuration& c, const std::string& turbine_id, uint64_t revision,
                                     const std::string& arbiter_id, double t) {
  windfdi::ControlConfiguration out;
  out.t(t);
  out.turbine_id(turbine_id);
  out.revision(revision);
  out.arbiter_id(arbiter_id);
  out.mode(bus::to_idl(c.mode));
  out.ipc_source(bus::to_idl(c.ipc_source));
  out.use_corrected_rotor_speed(c.use_corrected_rotor_speed);
  out.use_corrected_generator_speed(c.use_corrected_generator_speed);
  out.use_corrected_pitch(c.use_corrected_pitch);
  out.pitch_rate_limit(c.pitch_rate_limit);
  out.ice_mode(bus::to_idl(c.ice_mode));
  out.inertia(c.inertia);
  out.torque_compensation(c.torque_compensation);
  for (const auto& r : c.reasons) {
    if (out.reasons().size() >= 32) break;  // IDL bound; the most important are first after sorting
    windfdi::ConfigurationReason reason;
    reason.source(r.source);
    reason.component(r.component);
    windfdi::FaultClass fc = windfdi::FAULT_NONE;
    bus::fault_class_from_name(r.fault, fc);
    reason.fault_class(fc);
    reason.action(r.action);
    out.reasons().push_back(reason);
  }
  return out;
}

ArbiterNode::ArbiterNode(const CommonOptions& common, const ArbiterConfig& config, const NodeOptions& options)
    : common_(common),
      served_(common.turbines),
      limit_(common.max_turbines, "arbiter"),
      config_(config),
      options_(options),
      participant_([&] {
        auto p = participant_options(common, "windfdi-arbiter");
        p.shared_memory = options.shared_memory;
        return p;
      }()),
      report_wakeup_([this] { return report_arrived(); }),
      faults_(participant_, common.turbines, &report_wakeup_),
      health_in_(participant_, common.turbines, nullptr),
      inertia_(participant_, common.turbines, nullptr),
      pitch_(participant_, common.turbines, nullptr),
      acks_(participant_, common.turbines, &wakeup_),
      config_out_(
          participant_, "control",
          [&](eprosima::fastdds::dds::DataWriterQos& q) { q.ownership_strength().value = options.strength; }),
      health_(participant_, "arbiter", common.turbines),
      trace_("arbiter") {}

bool ArbiterNode::serves(const std::string& id) {
  return id != "*" && served_.contains(id) && limit_.admit(id);
}

ArbiterNode::Turbine& ArbiterNode::turbine(const std::string& id) {
  auto it = turbines_.find(id);
  if (it == turbines_.end()) {
    it = turbines_.emplace(id, Turbine{Arbiter(config_), {}, 0, -1e300, {}, {}, true}).first;
    spdlog::info("arbitrating turbine {}", id);
  }
  return it->second;
}

void ArbiterNode::apply_liveliness(const std::string& instance_turbine, const std::string& service,
                                   bool alive, double wall) {
  // "*": an instance that has not named a turbine yet; it speaks for the turbines no instance named.
  for (auto& [id, t] : turbines_)
    if (instance_turbine == id || (instance_turbine == "*" && liveliness_.alive(id, service) == alive)) {
      t.arbiter.on_service_alive(service, alive, t.clock.now(wall));
      t.dirty = true;
    }
}

void ArbiterNode::handle_inputs(double wall) {
  // Sample time first: every timer of the decision runs on the turbine's clock.
  // Taken at the next pass, not woken for: their reception time keeps the clock right.
  std::vector<windfdi::PitchActuatorEstimate> pitch;
  std::vector<bus::SampleMeta> meta;
  pitch_.take(pitch, &meta);
  for (std::size_t i = 0; i < pitch.size(); ++i)
    if (serves(pitch[i].turbine_id()) && std::isfinite(pitch[i].t()))
      turbine(pitch[i].turbine_id()).clock.observe(pitch[i].t(), meta[i].reception_time);
  std::vector<windfdi::FaultReport> reports;
  faults_.take(reports, &meta);
  const double taken = wall_time();
  for (std::size_t i = 0; i < reports.size(); ++i) {
    const auto& r = reports[i];
    const FaultEvent e = bus::to_event(r);
    if (foreign_reports_.refuse(e) || !serves(r.turbine_id())) continue;
    health_.count_in(r.turbine_id());
    Turbine& t = turbine(r.turbine_id());
    t.dirty = true;
    if (trace_.on()) {
      const std::string key = HopTrace::report_key(e.component, e.fault, e.t);
      trace_.record("report_receive", r.turbine_id(), key, meta[i].reception_time);
      trace_.record("report_take", r.turbine_id(), key, taken);
      t.traced_reports.push_back(key);
    }
    if (std::isfinite(e.t)) t.clock.observe(e.t, wall);
    if (!t.arbiter.on_fault(e, t.clock.now(wall))) {
      health_.count_rejected(r.turbine_id());
      spdlog::warn("{}: ignoring FaultReport {} / {} from {}: not a valid component and class",
                   r.turbine_id(), e.component, e.fault, e.source);
    }
  }

  // The loop passes every 0.1 s; a gap longer than kStallGap is this process stood still (SIGSTOP, a paused
  // VM, swapping). Checked here, not in the loop: a FaultReport's listener may run this first after a thaw.
  if (last_pass_ > 0.0 && wall - last_pass_ > kStallGap) {
    spdlog::warn(
        "arbiter: stood still for {:.1f} s; service losses seen in the next {:.0f} s count only if "
        "they last",
        wall - last_pass_, kStallGrace);
    stalled_until_ = wall + kStallGrace;
    last_pass_ = wall;
  }
  const auto admit = [this](const windfdi::ServiceHealth& h) {
    return is_health_source(h.service()) && (h.turbine_id() == "*" || serves(h.turbine_id()));
  };
  for (const auto& c : liveliness_.poll(health_in_, nullptr, admit)) {
    if (c.service == "arbiter") continue;
    // The plant and farm monitors report health too (the plant's first sample makes its turbines known); a
    // lost farm monitor is no lost diagnostic service and the decision ignores it, so it is not logged as
    // one.
    const bool diagnostic =
        std::find(service_names().begin(), service_names().end(), c.service) != service_names().end();
    if (!c.alive && diagnostic && wall < stalled_until_) {
      // Decided at the end of the grace, on the liveliness then.
      deferred_losses_.emplace(c.turbine_id, c.service);
      continue;
    }
    if (c.alive && deferred_losses_.erase({c.turbine_id, c.service}))
      spdlog::info("service {} for turbine {} alive again within the grace after the stall", c.service,
                   c.turbine_id);
    if (!c.alive && diagnostic)
      spdlog::warn("service {} for turbine {} lost its liveliness", c.service, c.turbine_id);
    apply_liveliness(c.turbine_id, c.service, c.alive, wall);
    if (c.alive && serves(c.turbine_id)) {
      Turbine& t = turbine(c.turbine_id);
      t.arbiter.on_service_alive(c.service, true, t.clock.now(wall));
      t.dirty = true;
    }
  }

  // Only the losses deferred are applied: one applied before the stall was logged and acted on then.
  if (!deferred_losses_.empty() && wall >= stalled_until_) {
    for (const auto& [turbine_id, service] : deferred_losses_) {
      if (liveliness_.alive(turbine_id, service)) continue;
      spdlog::warn("service {} for turbine {} lost its liveliness", service, turbine_id);
      apply_liveliness(turbine_id, service, false, wall);
    }
    deferred_losses_.clear();
  }

  std::vector<windfdi::InertiaEstimate> inertia;
  inertia_.take(inertia, &meta);
  for (std::size_t i = 0; i < inertia.size(); ++i) {
    const auto& est = inertia[i];
    if (!serves(est.turbine_id())) continue;
    Turbine& t = turbine(est.turbine_id());
    if (std::isfinite(est.t())) t.clock.observe(est.t(), meta[i].reception_time);
    if (std::isfinite(est.inertia()) && est.inertia() > 0) t.arbiter.on_inertia(est.inertia());
    t.dirty = true;
  }

  std::vector<windfdi::FaultAck> acks;
  acks_.take(acks);
  for (const auto& a : acks) {
    if (!serves(a.turbine_id())) continue;
    spdlog::info("{}: acknowledgement of {} on {} by {}", a.turbine_id(),
                 bus::fault_class_name(a.fault_class()), a.component(), a.operator_name());
    Turbine& t = turbine(a.turbine_id());
    t.arbiter.on_ack(a.component(), bus::fault_class_name(a.fault_class()), t.clock.now(wall));
    t.dirty = true;
  }
}

void ArbiterNode::publish_configurations(double wall) {
  // A (re)started arbiter decides once the services' transient-local reports are in: a restarted primary
  // published "no fault" for 5 ms before the replayed pump wear (the reliability campaign), and took the
  // turbine from the standby that knew it.
  if (wall - started_at_ < kStartupHold) return;
  // Every turbine is decided on every full pass (held decisions, republishing); between them only the
  // turbines an input came for. Deciding on every turbine for every input, and waking for every health
  // sample and estimate, cost a quarter of the arbiter's CPU at 480 turbines.
  const bool full = wall - last_full_pass_ >= kFullPassPeriod;
  if (full) last_full_pass_ = wall;
  for (auto& [id, t] : turbines_) {
    if (!full && !t.dirty) continue;
    t.dirty = false;
    const double now = t.clock.now(wall);
    const Configuration c = t.arbiter.evaluate(now);
    // The reports taken in this pass change the configuration now or not at all (a held decision changes it
    // later, from the timer).
    std::vector<std::string> traced;
    traced.swap(t.traced_reports);
    const bool changed = c != t.last || t.revision == 0;
    if (!changed && wall - t.last_published < options_.republish_period) continue;
    if (changed) t.revision = t.revision == 0 ? revision_base_ : t.revision + 1;
    t.last = c;
    t.last_published = wall;
    // Written before anything is logged: the plant waits for it, nobody waits for the log.
    if (trace_.on() && changed) trace_.record("config_write", id, std::to_string(t.revision), wall_time());
    if (!config_out_.write(to_idl(c, id, t.revision, options_.arbiter_id, now)))
      spdlog::error("{}: configuration not written", id);
    if (changed) {
      for (const auto& key : traced)
        trace_.record("report_config", id, key + ">" + std::to_string(t.revision), wall);
      spdlog::info("{}: configuration r{}: mode {}, ipc {}, ice {}, pitch rate {}/{}/{} deg/s, {} reasons",
                   id, t.revision, to_string(c.mode), to_string(c.ipc_source), to_string(c.ice_mode),
                   c.pitch_rate_limit[0], c.pitch_rate_limit[1], c.pitch_rate_limit[2], c.reasons.size());
      for (const auto& r : c.reasons)
        spdlog::info("{}:   because {} reported {} on {}: {}", id, r.source, r.fault, r.component, r.action);
    }
  }
}

bool ArbiterNode::report_arrived() {
  // Never waits for the loop (a listener blocked on it could hold DDS locks the loop's take needs): busy
  // or not yet running, the loop takes the report on its next pass, woken as for any other input.
  std::unique_lock<std::mutex> lock(step_mutex_, std::try_to_lock);
  if (!lock.owns_lock() || !running_) {
    wakeup_.notify();
    return true;
  }
  const double now = wall_time();
  handle_inputs(now);
  publish_configurations(now);
  return true;
}

void ArbiterNode::run() {
  {
    std::lock_guard<std::mutex> lock(step_mutex_);
    for (const auto& id : served_.ids()) turbine(id);
    health_.set_state(windfdi::SERVICE_OK);
    started_at_ = last_pass_ = wall_time();
    running_ = true;
  }
  spdlog::info("arbiter '{}' running with ownership strength {}", options_.arbiter_id, options_.strength);
  while (!shutdown_requested()) {
    wakeup_.wait_for(std::chrono::milliseconds(100));
    std::lock_guard<std::mutex> lock(step_mutex_);
    const double now = wall_time();
    handle_inputs(now);
    last_pass_ = now;
    publish_configurations(now);
    config_out_.assert_liveliness();
    health_.set_streams_of(faults_, health_in_, inertia_, pitch_, acks_, config_out_);
    health_.report_refusals(limit_, now);
    health_.tick(now);
  }
  std::lock_guard<std::mutex> lock(step_mutex_);
  running_ = false;
  health_.set_state(windfdi::SERVICE_STOPPING);
  health_.tick(wall_time(), true);
}

}  // namespace windfdi::arbiter
