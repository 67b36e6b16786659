// The fault-tolerant control arbiter's decision function (decision table: deploy/arbiter/DECISION_TABLE.md).
#include "decision.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

#include "names.hpp"
#include "turbine_params.hpp"

namespace windfdi::arbiter {

ArbiterConfig load_arbiter_config(const YamlSection& s) {
  s.require_known_keys({"clear_hold", "nominal_pitch_rate", "derated_pitch_rate", "rotor_speed_bias_limit",
                        "generator_speed_bias_limit", "pitch_bias_limit", "has_lidar", "inertia_step",
                        "stop_confirm_time", "class_settle_time", "isolation_lead", "isolation_common_window",
                        "efficiency_derate_drop", "max_torque_compensation", "turbine_file",
                        "rotor_speed_bias_limit_share", "generator_speed_bias_limit_share",
                        "torque_compensation_share"});
  ArbiterConfig c;
  c.clear_hold = s.get_number("clear_hold", c.clear_hold, 0.0, 3600.0);
  c.nominal_pitch_rate = s.get_number("nominal_pitch_rate", c.nominal_pitch_rate, 1.0, 30.0);
  c.derated_pitch_rate = s.get_number("derated_pitch_rate", c.derated_pitch_rate, 0.5, 30.0);
  if (c.derated_pitch_rate > c.nominal_pitch_rate)
    throw s.error("derated_pitch_rate", "must not exceed nominal_pitch_rate");
  // Speed and torque limits are shares of the turbine's rated values (the absolute keys override them): a
  // 0.1 rad/s rotor speed bias is 5.9 % of the benchmark rotor's rated speed but 13 % of a rotor rated at 7.5
  // rpm.
  const TurbineParams turbine = configured_turbine(s);
  c.rotor_speed_bias_limit = s.get_number(
      "rotor_speed_bias_limit",
      s.get_number("rotor_speed_bias_limit_share", 0.0586, 0.0, 1.0) * turbine.rated_rotor_speed(), 0.0,
      10.0);
  c.generator_speed_bias_limit = s.get_number(
      "generator_speed_bias_limit",
      s.get_number("generator_speed_bias_limit_share", 0.0617, 0.0, 1.0) * turbine.rated_generator_speed, 0.0,
      1000.0);
  c.pitch_bias_limit = s.get_number("pitch_bias_limit", c.pitch_bias_limit, 0.0, 90.0);
  c.has_lidar = s.get<bool>("has_lidar", c.has_lidar);
  c.inertia_step = s.get_number("inertia_step", c.inertia_step, 0.0, 0.5);
  c.stop_confirm_time = s.get_number("stop_confirm_time", c.stop_confirm_time, 0.0, 600.0);
  c.class_settle_time = s.get_number("class_settle_time", c.class_settle_time, 0.0, 3600.0);
  c.efficiency_derate_drop = s.get_number("efficiency_derate_drop", c.efficiency_derate_drop, 0.0, 1.0);
  c.max_torque_compensation = s.get_number(
      "max_torque_compensation",
      s.get_number("torque_compensation_share", 0.0662, 0.0, 1.0) * turbine.rated_generator_torque(), 0.0,
      1e6);
  c.isolation.lead = s.get_number("isolation_lead", c.isolation.lead, 0.0, 600.0);
  c.isolation.common_window = s.get_number("isolation_common_window", c.isolation.common_window, 0.0, 600.0);
  return c;
}

bool Configuration::operator==(const Configuration& o) const {
  return mode == o.mode && ipc_source == o.ipc_source &&
         use_corrected_rotor_speed == o.use_corrected_rotor_speed &&
         use_corrected_generator_speed == o.use_corrected_generator_speed &&
         use_corrected_pitch == o.use_corrected_pitch && pitch_rate_limit == o.pitch_rate_limit &&
         ice_mode == o.ice_mode && inertia == o.inertia && torque_compensation == o.torque_compensation &&
         reasons == o.reasons;
}

Arbiter::Arbiter(const ArbiterConfig& config) : config_(config) {}

namespace {
std::string cause_key(const FaultEvent& e) { return e.source + "/" + e.component + "/" + e.fault; }
bool starts_with(const std::string& s, const char* p) { return s.rfind(p, 0) == 0; }
// A leak stops the turbine only when pitch_diag calls it critical: far enough along its path that it cannot
// be the pump wear (or a misread high air content) it shares the point alpha 0.5 with. Measured on the
// multi-fault suite: two such flips held "fault" for the class-settle time and stopped healthy-enough
// turbines.
bool stop_severity(const std::string& severity) { return severity == "critical"; }
}  // namespace

bool Arbiter::on_fault(const FaultEvent& e, double now) {
  const auto classes = fault_classes_for(e.component);
  if (!is_component(e.component) || std::find(classes.begin(), classes.end(), e.fault) == classes.end() ||
      e.fault == "service_lost" || name_index(severity_names(), e.severity) < 0) {
    ++rejected_;
    return false;
  }
  const std::string key = cause_key(e);
  if (e.raised) {
    Cause& c = causes_[key];
    if (!c.raised || c.event.severity != e.severity) c.severity_since = now;
    if (!c.raised) note_class(e, now);
    c.event = e;
    c.raised = true;
  } else {
    auto it = causes_.find(key);
    if (it == causes_.end()) return true;  // clearing something never raised here: nothing to undo
    if (it->second.raised) {
      it->second.cleared_at = now;
      note_class(e, now);  // a class counts as a rival until it was last active
    }
    it->second.raised = false;
    it->second.event.size = e.size;
  }
  return true;
}

void Arbiter::note_class(const FaultEvent& e, double now) {
  auto& h = class_history_[e.source + "/" + e.component];
  h.emplace_back(now, e.fault);
  while (h.size() > 1 && now - h.front().first > config_.class_settle_time) h.erase(h.begin());
}

std::vector<std::string> Arbiter::rival_classes(const Cause& c, double now) const {
  std::vector<std::string> out;
  const auto it = class_history_.find(c.event.source + "/" + c.event.component);
  if (it == class_history_.end()) return out;
  for (const auto& [t, cls] : it->second)
    if (now - t < config_.class_settle_time && cls != c.event.fault &&
        std::find(out.begin(), out.end(), cls) == out.end())
      out.push_back(cls);
  return out;
}

void Arbiter::on_ack(const std::string& component, const std::string& fault, double /*now*/) {
  for (auto& [key, c] : causes_) {
    if (c.event.component != component || (fault != "none" && c.event.fault != fault)) continue;
    c.latched = false;
    // An acknowledged fault that is already clear is released at once: the operator has looked at it.
    if (!c.raised) c.cleared_at = -std::numeric_limits<double>::infinity();
  }
}

void Arbiter::on_service_alive(const std::string& service, bool alive, double now) {
  if (name_index(service_names(), service) < 0) return;  // not a diagnostic service: no components
  if (!alive) {
    lost_services_[service] = now;
    recovered_services_.erase(service);
  } else if (lost_services_.erase(service)) {
    recovered_services_[service] = now;
  }
}

bool Arbiter::acting(const Cause& c, double now) const {
  return c.raised || c.latched || now - c.cleared_at < config_.clear_hold;
}

std::vector<std::string> Arbiter::active_causes(double now) const {
  std::vector<std::string> out;
  for (const auto& [key, c] : causes_)
    if (acting(c, now)) out.push_back(key);
  for (const auto& [s, t] : lost_services_) out.push_back(s + "/" + s + "/service_lost");
  return out;
}

namespace {
template <class E>
void demand(E& current, E wanted) {
  if (static_cast<int>(wanted) > static_cast<int>(current)) current = wanted;
}
}  // namespace

void Arbiter::apply(Cause& cause, double now, Configuration& cfg) {
  const FaultEvent& e = cause.event;
  auto reason = [&](const std::string& action) {
    cfg.reasons.push_back({e.source, e.component, e.fault, action});
  };
  const int blade = blade_index(e.component);

  if (starts_with(e.component, "blade_moment_sensor_")) {
    // Stotsky 2014's fault-tolerant IPC: the LIDAR load model replaces a failed strain gauge.
    const bool lidar_ok = config_.has_lidar && !lost_services_.count("blade_load");
    bool lidar_faulty = false;
    for (const auto& [k, c] : causes_)
      if (c.event.component == "lidar" && c.raised) lidar_faulty = true;
    const IpcSource wanted = (lidar_ok && !lidar_faulty) ? IpcSource::kLidarModel : IpcSource::kOff;
    demand(cfg.ipc_source, wanted);
    reason(std::string("ipc_source=") + to_string(wanted));
  } else if (e.component == "lidar") {
    if (cfg.ipc_source == IpcSource::kLidarModel) cfg.ipc_source = IpcSource::kOff;
    reason("lidar_model_unavailable");
  } else if (e.component == "rotor_speed_sensor" || e.component == "generator_speed_sensor" ||
             starts_with(e.component, "pitch_sensor_")) {
    const double limit = e.component == "rotor_speed_sensor"       ? config_.rotor_speed_bias_limit
                         : e.component == "generator_speed_sensor" ? config_.generator_speed_bias_limit
                                                                   : config_.pitch_bias_limit;
    if (e.fault == "sensor_bias" || e.fault == "sensor_stuck" || e.fault == "sensor_gain") {
      // A stuck or scaled reading is replaced like a biased one: sensor_bias's corrected value is the
      // observer's estimate, which for a speed sensor rests on the other speed sensor through the gear ratio
      // and on the power witness.
      if (e.component == "rotor_speed_sensor") cfg.use_corrected_rotor_speed = true;
      if (e.component == "generator_speed_sensor") cfg.use_corrected_generator_speed = true;
      if (blade >= 0 && starts_with(e.component, "pitch_sensor_")) cfg.use_corrected_pitch[blade] = true;
      reason("use_corrected_" + e.component);
    }
    if (e.fault == "sensor_invalid" || !(std::fabs(e.size) <= limit)) {
      demand(cfg.mode, Mode::kDegraded);
      reason("mode=degraded (measurement not trusted)");
    }
  } else if (starts_with(e.component, "pitch_actuator_") && blade >= 0) {
    const auto rivals = rival_classes(cause, now);
    // A stop needs strong, settled evidence: the leak class at critical severity for stop_confirm_time, and
    // no other class on this actuator for class_settle_time. Short of that, the reversible derate.
    const bool stop_class = e.fault == "hydraulic_leakage";
    if (stop_class && (cause.latched || (rivals.empty() && cause.raised && stop_severity(e.severity) &&
                                         now - cause.settled_since() >= config_.stop_confirm_time))) {
      cause.latched = true;
      demand(cfg.mode, Mode::kSafeStop);
      reason("mode=safe_stop");
      return;
    }
    cfg.pitch_rate_limit[blade] = std::min(cfg.pitch_rate_limit[blade], config_.derated_pitch_rate);
    std::string classes = e.fault;
    for (const auto& r : rivals) classes += " or " + r;
    if (!rivals.empty()) {
      // Uncertain between classes: the most conservative reversible action of any candidate.
      demand(cfg.mode, Mode::kDegraded);
      reason("uncertain: " + classes + "; mode=degraded, pitch_rate_limit_" + std::to_string(blade + 1) +
             "=derated");
    } else if (stop_class) {
      demand(cfg.mode, Mode::kDegraded);
      reason("mode=degraded, pitch_rate_limit_" + std::to_string(blade + 1) +
             "=derated; safe stop when confirmed");
    } else {
      reason("pitch_rate_limit_" + std::to_string(blade + 1) + "=derated; maintenance");
    }
  } else if (e.component == "rotor") {
    const bool critical_confirmed =
        e.fault == "ice_accretion" &&
        (cause.latched || (cause.raised && e.severity == "critical" &&
                           now - cause.settled_since() >= config_.stop_confirm_time));
    if (critical_confirmed) {
      cause.latched = true;
      demand(cfg.ice_mode, IceMode::kStop);
      demand(cfg.mode, Mode::kSafeStop);
      reason("ice_mode=stop");
    } else if (e.fault == "ice_accretion") {
      demand(cfg.ice_mode, IceMode::kAdapted);
      reason("ice_mode=adapted");
    } else {
      reason("farm_alarm");
    }
  } else if (e.component == "converter" && e.fault == "torque_offset") {
    // The benchmark's converter offset: the command is corrected by the estimated offset, so the generator
    // gives the torque the controller asked for; the converter needs service.
    if (std::fabs(e.size) <= config_.max_torque_compensation) {
      cfg.torque_compensation = e.size;
      reason("torque_compensation=" + std::to_string(static_cast<long>(std::lround(e.size))) +
             " N m; maintenance");
    } else {
      demand(cfg.mode, Mode::kDegraded);
      reason("mode=degraded (offset beyond compensation); maintenance");
    }
  } else if (e.component == "drive_train" && e.fault == "efficiency_loss") {
    if (e.size >= config_.efficiency_derate_drop) {
      demand(cfg.mode, Mode::kDegraded);
      reason("mode=degraded (efficiency loss beyond efficiency_derate_drop); maintenance");
    } else {
      reason("maintenance");
    }
  }
  // Any other critical report latches once it has held for stop_confirm_time (an actuator's latches only with
  // the stop it settled into, above: an uncertain critical leak stays reversible).
  if (!starts_with(e.component, "pitch_actuator_") && cause.raised && e.severity == "critical" &&
      now - cause.settled_since() >= config_.stop_confirm_time)
    cause.latched = true;
}

void Arbiter::apply_service_lost(const std::string& service, Configuration& cfg) const {
  auto reason = [&](const std::string& action) {
    cfg.reasons.push_back({service, service, "service_lost", action});
  };
  if (service == "blade_load") {
    // Nobody watches the strain gauges or the LIDAR: individual pitch control is off.
    cfg.ipc_source = IpcSource::kOff;
    reason("ipc_source=off");
  } else if (service == "sensor_bias") {
    // The corrected measurements stop arriving and biases go unseen.
    cfg.use_corrected_rotor_speed = cfg.use_corrected_generator_speed = false;
    cfg.use_corrected_pitch = {false, false, false};
    demand(cfg.mode, Mode::kDegraded);
    reason("mode=degraded; corrected measurements off");
  } else if (service == "pitch_diag") {
    for (auto& r : cfg.pitch_rate_limit) r = std::min(r, config_.derated_pitch_rate);
    demand(cfg.mode, Mode::kDegraded);
    reason("mode=degraded; pitch rate derated on every blade");
  } else if (service == "ice_detect") {
    demand(cfg.mode, Mode::kDegraded);
    reason("mode=degraded (icing unobserved)");
  }
}

Configuration Arbiter::evaluate(double now) {
  Configuration cfg;
  cfg.pitch_rate_limit = {config_.nominal_pitch_rate, config_.nominal_pitch_rate, config_.nominal_pitch_rate};
  // Isolation: a report that another acting report explains (signature table) is secondary and not acted
  // on; a latched cause has been acted on and stays until acknowledged.
  std::vector<Cause*> acting_causes;
  std::vector<isolation::Report> reports;
  for (auto& [key, c] : causes_)
    if (acting(c, now)) {
      acting_causes.push_back(&c);
      reports.push_back({c.event.source, c.event.component, c.event.fault, c.event.t_detected});
    }
  const auto verdicts = isolation::isolate(reports, config_.isolation);
  for (std::size_t i = 0; i < acting_causes.size(); ++i) {
    Cause& c = *acting_causes[i];
    // A stop's clock runs from when the cause became a root: a leak that was explained by its blade's
    // pitch-sensor bias until that cleared had held its severity for minutes, and would have stopped the
    // turbine the moment the bias's clear_hold ran out.
    if (c.secondary && !verdicts[i].secondary) c.primary_since = now;
    c.secondary = verdicts[i].secondary;
    if (verdicts[i].secondary && !c.latched)
      cfg.reasons.push_back({c.event.source, c.event.component, c.event.fault,
                             "secondary: explained by " + verdicts[i].explained_by + " (not acted on)"});
    else
      apply(c, now, cfg);
  }
  // A service lost (or back for less than clear_hold) overrides what its own reports asked for.
  for (auto it = recovered_services_.begin(); it != recovered_services_.end();) {
    if (now - it->second >= config_.clear_hold) {
      it = recovered_services_.erase(it);
    } else {
      apply_service_lost(it->first, cfg);
      ++it;
    }
  }
  for (const auto& [service, t] : lost_services_) apply_service_lost(service, cfg);
  if (cfg.ice_mode == IceMode::kAdapted) cfg.inertia = inertia_;
  std::sort(cfg.reasons.begin(), cfg.reasons.end(), [](const Reason& a, const Reason& b) {
    return std::tie(a.source, a.component, a.fault, a.action) <
           std::tie(b.source, b.component, b.fault, b.action);
  });
  cfg.reasons.erase(std::unique(cfg.reasons.begin(), cfg.reasons.end()), cfg.reasons.end());
  return cfg;
}

}  // namespace windfdi::arbiter
