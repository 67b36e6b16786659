// The farm monitor's DDS node.
#include "farm_node.hpp"

#include <spdlog/spdlog.h>
#include <unistd.h>

#include <iostream>

#include "dds/convert.hpp"
#include "farm_cli.hpp"
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
  r.arbiter_id = c.arbiter_id();
  r.revision = c.revision();
  r.mode = setting_name(c.mode(), windfdi::MODE_SAFE_STOP);
  r.ipc_source = setting_name(c.ipc_source(), windfdi::IPC_OFF);
  r.ice_mode = setting_name(c.ice_mode(), windfdi::ICE_STOP);
  for (const auto& reason : c.reasons())
    r.reasons.push_back(reason.source() + "/" + reason.component() + "/" +
                        bus::fault_class_name(reason.fault_class()) + ": " + reason.action());
  return r;
}

FarmNode::FarmNode(const CommonOptions& common, const FarmOptions& options)
    : options_(options),
      store_(options.db),
      participant_(participant_options(common, "windfdi-farm")),
      faults_(participant_, common.turbines, &wakeup_),
      configs_(participant_, common.turbines, &wakeup_),
      health_(participant_, common.turbines, &wakeup_) {
  // The picture survives a restart: start from what the database already knows.
  for (const auto& e : store_.latest_faults()) state_.on_fault(e);
  spdlog::info("farm monitor: database {} holds {} fault events, {} configurations", options.db,
               store_.count("fault_events"), store_.count("configurations"));
  if (!options.http.listen.empty()) {
    const std::string token = options.http.token_file.empty() ? "" : read_token(options.http.token_file);
    acks_ = std::make_unique<bus::Writer<windfdi::FaultAck>>(participant_);
    api_ = std::make_unique<FarmApi>(options.db, token,
                                     [this](const std::string& turbine, const std::string& component,
                                            const std::string& fault, const std::string& operator_name) {
                                       return publish_ack(turbine, component, fault, operator_name);
                                     });
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

void FarmNode::handle(double now) {
  std::vector<windfdi::FaultReport> reports;
  faults_.take(reports);
  for (const auto& r : reports) {
    const FaultEvent e = bus::to_event(r);
    if (store_.add_fault(e, now))
      spdlog::info("{} {} {} {} ({}) from {}", e.turbine_id, e.component, e.fault,
                   e.raised ? "RAISED" : "cleared", e.severity, e.source);
    state_.on_fault(e);
  }
  std::vector<windfdi::ControlConfiguration> configs;
  configs_.take(configs);
  for (const auto& c : configs) {
    const ConfigRecord rec = to_record(c, now);
    if (store_.add_config(rec))
      spdlog::info("{} configuration r{} from {}: mode {}, ipc {}, ice {}", rec.turbine_id, rec.revision,
                   rec.arbiter_id, rec.mode, rec.ipc_source, rec.ice_mode);
    state_.on_config(rec);
  }
  std::vector<windfdi::ServiceHealth> health;
  bool lost_any = false;
  for (const auto& c : liveliness_.poll(health_, &health)) {
    if (c.alive) continue;
    lost_any = true;
    spdlog::warn("{}: service {} lost (liveliness)", c.turbine_id, c.service);
    service_state_[c.turbine_id + "/" + c.service] = "lost";
    store_.add_health({now, c.turbine_id, c.service, "lost", "liveliness lost"});
    state_.on_service_lost(c.turbine_id, c.service);
    metrics_[c.turbine_id + "/" + c.service].state = "lost";
  }
  for (const auto& h : health) {
    const std::string state = pick(kServiceStates, h.state());
    const std::string key = h.turbine_id() + "/" + h.service();
    if (service_state_[key] != state) {
      service_state_[key] = state;
      store_.add_health({now, h.turbine_id(), h.service(), state, h.detail()});
    }
    state_.on_service(h.turbine_id(), h.service(), state);
    metrics_[key] = {state,  h.samples_in(), h.samples_rejected(), h.sequence_gaps(), h.deadlines_missed(),
                     h.lag()};
  }
  // The web side gets a copy only when something came in (200 turbines' picture is copied in well under 1
  // ms).
  if (api_ && (!reports.empty() || !configs.empty() || !health.empty() || lost_any))
    api_->update(state_, metrics_);
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
