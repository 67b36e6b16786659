// The farm monitor's DDS node.
#include "farm_node.hpp"

#include <spdlog/spdlog.h>
#include <unistd.h>

#include <iostream>

#include "dds/convert.hpp"
#include "farm_cli.hpp"
#include "names.hpp"
#include "yaml_config.hpp"

namespace windfdi::farm {

namespace {
// The canonical name of a control setting (common/control_modes.hpp); a value beyond the enum shows as such.
template <class IdlEnum>
std::string setting_name(IdlEnum v, IdlEnum last) {
  return static_cast<int>(v) >= 0 && static_cast<int>(v) <= static_cast<int>(last)
             ? control::to_string(bus::from_idl(v))
             : "unknown";
}
const char* kServiceStates[] = {"starting", "ok", "degraded", "stopping"};
// The farm monitor's own name on wt/health; it is no diagnostic service of a turbine.
const std::string kSelf = "farm_monitor";
// Events kept in memory while the store fails: about 100 MB, hours of a farm's events (its health changes
// and configurations are far fewer than that a minute).
constexpr std::size_t kBacklogCapacity = 500000;
template <std::size_t N>
std::string pick(const char* (&names)[N], int i) {
  return (i >= 0 && static_cast<std::size_t>(i) < N) ? names[i] : "unknown";
}
}  // namespace

ConfigRecord to_record(const windfdi::ControlConfiguration& c, double received_at) {
  ConfigRecord r;
  r.received_at = received_at;
  r.t = c.t();
  r.turbine_id = c.turbine_id();
  r.arbiter_id = c.arbiter_id().substr(0, kMaxTurbineIdLength);
  r.revision = c.revision();
  r.mode = setting_name(c.mode(), windfdi::MODE_SAFE_STOP);
  r.ipc_source = setting_name(c.ipc_source(), windfdi::IPC_OFF);
  r.ice_mode = setting_name(c.ice_mode(), windfdi::ICE_STOP);
  for (const auto& reason : c.reasons())
    r.reasons.push_back((reason.source() + "/" + reason.component() + "/" +
                         bus::fault_class_name(reason.fault_class()) + ": " + reason.action())
                            .substr(0, kMaxReportDetail));
  return r;
}

FarmNode::FarmNode(const CommonOptions& common, const FarmOptions& options)
    : options_(options),
      store_(options.db),
      backlog_(store_, kBacklogCapacity, [this](const StoreBacklog::Record& r) { on_stored(r); }),
      participant_(participant_options(common, "windfdi-farm")),
      faults_(participant_, common.turbines, &wakeup_),
      configs_(participant_, common.turbines, &wakeup_),
      health_(participant_, common.turbines, &wakeup_),
      // The estimates are not waited for: they are stored at estimate_period when the loop passes.
      blade_estimates_(participant_, common.turbines),
      // The newest sensor_bias estimate per turbine, best effort: the store keeps one a second, and a
      // reliable reader of every turbine's 100 Hz estimate was the farm monitor's largest cost (its
      // heartbeats and acknowledgements; 40 % of a core with 20 turbines at 10x, the soak's limit).
      bias_estimates_(participant_, common.turbines, nullptr, "estimate_newest"),
      pitch_estimates_(participant_, common.turbines),
      inertia_estimates_(participant_, common.turbines),
      drive_train_estimates_(participant_, common.turbines),
      limit_(common.max_turbines, "farm_monitor") {
  try {
    self_health_ = std::make_unique<HealthReporter>(participant_, kSelf, std::vector<std::string>{});
  } catch (const std::exception& e) {
    spdlog::warn(
        "farm monitor: its own health is not published ({}; credentials made before it was granted "
        "wt/health: deploy/security/make_credentials.sh)",
        e.what());
  }
  // The picture survives a restart: start from what the database already knows.
  for (const auto& e : store_.latest_faults()) state_.on_fault(e);
  spdlog::info("farm monitor: database {} holds {} fault events, {} configurations", options.db,
               store_.count("fault_events"), store_.count("configurations"));
  if (!options.http.listen.empty()) {
    const std::string token = options.http.token_file.empty() ? "" : read_token(options.http.token_file);
    acks_ = std::make_unique<bus::Writer<windfdi::FaultAck>>(participant_);
    api_ = std::make_unique<FarmApi>(
        options.db, token,
        [this](const std::string& turbine, const std::string& component, const std::string& fault,
               const std::string& operator_name) {
          return publish_ack(turbine, component, fault, operator_name);
        },
        options.report_scenario);
    api_->update(state_, metrics_);
    http_ = std::make_unique<FarmHttp>(options.http, *api_);
    if (token.empty())
      spdlog::warn("farm monitor: no operator token: the web API is read-only, localhost only");
  }
}

int FarmNode::publish_ack(const std::string& turbine, const std::string& component, const std::string& fault,
                          const std::string& operator_name) {
  const windfdi::FaultAck ack = make_ack(turbine, component, fault, operator_name, "fault or component");
  if (!acks_->write(ack)) throw std::runtime_error("FaultAck not written");
  spdlog::info("{}: {} acknowledged {} on {} from the web page ({} arbiters)", turbine, operator_name, fault,
               component, acks_->matched());
  return static_cast<int>(acks_->matched());
}

namespace {
template <class Array>
nlohmann::json blades(const Array& a) {
  return nlohmann::json(std::vector<double>(a.begin(), a.end()));
}
}  // namespace

void FarmNode::sample(const std::string& turbine, const std::string& service, double t, nlohmann::json fields,
                      double now) {
  if (!limit_.admit(turbine)) return;
  const auto last = estimate_stored_at_.find(turbine + "/" + service);
  if (last != estimate_stored_at_.end() && t >= last->second &&
      t - last->second < options_.estimate_period - 1e-9)
    return;
  estimate_stored_at_[turbine + "/" + service] = t;
  estimate_batch_.push_back({now, t, turbine, service, std::move(fields)});
}

void FarmNode::store_estimates(double now) {
  std::vector<windfdi::BladeLoadEstimate> blade;
  blade_estimates_.take(blade);
  std::vector<windfdi::SensorBiasEstimate> bias;
  bias_estimates_.take(bias);
  std::vector<windfdi::PitchActuatorEstimate> pitch;
  pitch_estimates_.take(pitch);
  std::vector<windfdi::InertiaEstimate> inertia;
  inertia_estimates_.take(inertia);
  std::vector<windfdi::DriveTrainEstimate> drive;
  drive_train_estimates_.take(drive);
  if (options_.estimate_period <= 0.0) return;
  for (const auto& e : blade)
    sample(e.turbine_id(), "blade_load", e.t(),
           {{"a1_sensor", blades(e.a1_sensor())},
            {"a1_model", blades(e.a1_model())},
            {"lidar_ok", e.lidar_ok()}},
           now);
  for (const auto& e : bias)
    sample(e.turbine_id(), "sensor_bias", e.t(),
           {{"bias_rotor_speed", e.bias_rotor_speed()},
            {"bias_generator_speed", e.bias_generator_speed()},
            {"bias_pitch", blades(e.bias_pitch())},
            {"bound_ratio", e.bound_ratio()}},
           now);
  for (const auto& e : pitch)
    sample(e.turbine_id(), "pitch_diag", e.t(),
           {{"omega_n", blades(e.omega_n())}, {"zeta", blades(e.zeta())}, {"alpha", blades(e.alpha())}}, now);
  for (const auto& e : inertia)
    sample(e.turbine_id(), "ice_detect", e.t(),
           {{"inertia", e.inertia()},
            {"inertia_clean", e.inertia_clean()},
            {"ice_mass", e.ice_mass()},
            {"excited", e.excited()},
            {"warning_rise", e.warning_rise()},
            {"fault_rise", e.fault_rise()},
            {"critical_rise", e.critical_rise()}},
           now);
  for (const auto& e : drive)
    sample(e.turbine_id(), "drive_train", e.t(),
           {{"torque_offset", e.torque_offset()},
            {"torque_statistic", e.torque_statistic()},
            {"efficiency", e.efficiency()},
            {"efficiency_reference", e.efficiency_reference()}},
           now);
  backlog_.add_estimates(estimate_batch_);
  estimate_batch_.clear();
  if (now - pruned_at_ >= kPrunePeriod && backlog_.error().empty()) {
    pruned_at_ = now;
    try {
      store_.prune_estimates(now - 3600.0 * options_.estimate_retention);
    } catch (const std::exception& e) {
      spdlog::warn("farm store: old estimates not pruned: {}", e.what());
    }
  }
}

void FarmNode::handle(double now) {
  std::vector<windfdi::FaultReport> reports;
  faults_.take(reports);
  for (const auto& r : reports) {
    const FaultEvent e = bus::to_event(r);
    // A foreign report is neither stored nor shown.
    if (foreign_reports_.refuse(e) || !limit_.admit(r.turbine_id())) continue;
    backlog_.add(StoreBacklog::Fault{e, now});
    state_.on_fault(e);
  }
  std::vector<windfdi::ControlConfiguration> configs;
  configs_.take(configs);
  for (const auto& c : configs) {
    if (!limit_.admit(c.turbine_id())) continue;
    ConfigRecord rec = to_record(c, now);
    state_.on_config(rec);
    backlog_.add(std::move(rec));
  }
  std::vector<windfdi::ServiceHealth> health;
  bool lost_any = false;
  const auto admit = [this](const windfdi::ServiceHealth& h) {
    return is_health_source(h.service()) && limit_.admit(h.turbine_id());
  };
  for (const auto& c : liveliness_.poll(health_, &health, admit)) {
    if (c.alive) continue;
    lost_any = true;
    spdlog::warn("{}: service {} lost (liveliness)", c.turbine_id, c.service);
    metrics_[c.turbine_id + "/" + c.service].state = "lost";
    backlog_.add(HealthRecord{now, c.turbine_id, c.service, "lost", "liveliness lost"});
    if (c.service == kSelf) continue;  // another farm monitor: no service of a turbine
    if (c.turbine_id != "*") {
      state_.on_service_lost(c.turbine_id, c.service);
      continue;
    }
    // An instance lost before it named a turbine: the turbines no other instance (a shard on another host)
    // speaks for.
    for (const auto& [id, t] : state_.turbines())
      if (!liveliness_.alive(id, c.service)) state_.on_service_lost(id, c.service);
  }
  for (const auto& h : health) {
    if (h.service() == kSelf) continue;  // its own (keep_store_health) or another farm monitor's
    const std::string state = pick(kServiceStates, h.state());
    ServiceMetrics& m = metrics_[h.turbine_id() + "/" + h.service()];
    if (m.state != state) backlog_.add(HealthRecord{now, h.turbine_id(), h.service(), state, h.detail()});
    m = {state, h.samples_in(), h.samples_rejected(), h.sequence_gaps(), h.deadlines_missed(), h.lag()};
    if (h.turbine_id() != "*") {
      state_.on_service(h.turbine_id(), h.service(), state);
      continue;
    }
    // An instance that has not named a turbine yet: its state is not that of the turbines an instance named.
    for (const auto& [id, t] : state_.turbines())
      if (!liveliness_.named(id, h.service())) state_.on_service(id, h.service(), state);
  }
  store_estimates(now);
  keep_store_health(now);
  // The web side gets a copy only when something came in (200 turbines' picture is copied in well under 1
  // ms).
  if (api_ && (!reports.empty() || !configs.empty() || !health.empty() || lost_any))
    api_->update(state_, metrics_);
}

void FarmNode::on_stored(const StoreBacklog::Record& record) {
  if (const auto* f = std::get_if<StoreBacklog::Fault>(&record)) {
    const FaultEvent& e = f->event;
    spdlog::info("{} {} {} {} ({}) from {}", e.turbine_id, e.component, e.fault,
                 e.raised ? "RAISED" : "cleared", e.severity, e.source);
  } else if (const auto* c = std::get_if<ConfigRecord>(&record)) {
    spdlog::info("{} configuration r{} from {}: mode {}, ipc {}, ice {}", c->turbine_id, c->revision,
                 c->arbiter_id, c->mode, c->ipc_source, c->ice_mode);
  }
}

void FarmNode::keep_store_health(double now) {
  switch (backlog_.flush(now)) {
    case StoreBacklog::Change::kFailed:
      spdlog::error(
          "farm store {}: cannot write ({}); the farm monitor goes on and keeps up to {} events in "
          "memory until it can",
          options_.db, backlog_.error(), kBacklogCapacity);
      break;
    case StoreBacklog::Change::kRecovered:
      spdlog::info(
          "farm store {}: writing again after {:.0f} s; every event kept was written{}", options_.db,
          now - backlog_.failing_since(),
          backlog_.dropped() ? " (" + std::to_string(backlog_.dropped()) + " dropped past the limit)" : "");
      break;
    case StoreBacklog::Change::kNone:
      break;
  }
  if (backlog_.dropped() > dropped_logged_) {
    if (dropped_logged_ == 0)
      spdlog::error("farm store: {} events wait in memory; newer events are dropped until the store writes",
                    backlog_.waiting());
    dropped_logged_ = backlog_.dropped();
  }
  const std::string problem = backlog_.describe();
  const auto state = problem.empty() ? windfdi::SERVICE_OK : windfdi::SERVICE_DEGRADED;
  // Turbines refused past --max-turbines are said too (renewed once a second), but leave the farm monitor
  // ok: what it keeps is whole.
  if (!self_health_ || self_health_->due(now)) refused_note_ = limit_.describe();
  const std::string detail = problem + (problem.empty() || refused_note_.empty() ? "" : "; ") + refused_note_;
  if (self_health_) {
    self_health_->set_state(state, detail);
    self_health_->set_streams_of(faults_, configs_, health_);
    self_health_->tick(now);
  }
  // Also in /metrics and the page, with or without the DDS writer.
  ServiceMetrics& self = metrics_["*/" + kSelf];
  const std::string self_state = state == windfdi::SERVICE_OK ? "ok" : "degraded";
  if (self.state != self_state) backlog_.add(HealthRecord{now, "*", kSelf, self_state, detail});
  self.state = self_state;
}

void FarmNode::run() {
  const bool tty = isatty(STDOUT_FILENO);
  double last_table = 0.0;
  while (!shutdown_requested()) {
    wakeup_.wait_for(std::chrono::milliseconds(200));
    const double now = wall_time();
    handle(now);
    if (options_.table_period > 0 && now - last_table >= options_.table_period) {
      last_table = now;
      if (tty) std::cout << "\033[2J\033[H";
      std::cout << state_.render() << std::flush;
    }
  }
}

}  // namespace windfdi::farm
