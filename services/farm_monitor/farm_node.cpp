// The farm monitor's DDS node.
#include "farm_node.hpp"

#include <spdlog/spdlog.h>
#include <unistd.h>

#include <cmath>
#include <ctime>
#include <iostream>

#include "dds/convert.hpp"
#include "fault_report.hpp"
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
  for (const auto& c : liveliness_.poll(health_, &health)) {
    if (c.alive) continue;
    spdlog::warn("{}: service {} lost (liveliness)", c.turbine_id, c.service);
    service_state_[c.turbine_id + "/" + c.service] = "lost";
    store_.add_health({now, c.turbine_id, c.service, "lost", "liveliness lost"});
    state_.on_service_lost(c.turbine_id, c.service);
  }
  for (const auto& h : health) {
    const std::string state = pick(kServiceStates, h.state());
    const std::string key = h.turbine_id() + "/" + h.service();
    if (service_state_[key] != state) {
      service_state_[key] = state;
      store_.add_health({now, h.turbine_id(), h.service(), state, h.detail()});
    }
    state_.on_service(h.turbine_id(), h.service(), state);
  }
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

int publish_ack(const CommonOptions& common, const std::string& turbine, const std::string& component,
                const std::string& fault, const std::string& operator_name, double timeout_s) {
  windfdi::FaultClass fc = windfdi::FAULT_NONE;
  if (!bus::fault_class_from_name(fault, fc))
    throw ConfigError("--fault", 0, "", "'" + fault + "' is not a fault class");
  if (!is_component(component))
    throw ConfigError("COMPONENT", 0, "", "'" + component + "' is not a component");
  bus::Participant participant(participant_options(common, "windfdi-farm-ack"));
  bus::Writer<windfdi::FaultAck> writer(participant);
  writer.wait_for_readers(1, std::chrono::milliseconds(static_cast<int>(timeout_s * 1000)));
  windfdi::FaultAck ack;
  ack.t(wall_time());
  ack.turbine_id(turbine);
  ack.component(component);
  ack.fault_class(fc);
  ack.operator_name(operator_name);
  if (!writer.write(ack)) throw std::runtime_error("FaultAck not written");
  const bool acked = writer.get()->wait_for_acknowledgments(eprosima::fastrtps::Duration_t(
                         static_cast<int32_t>(std::ceil(timeout_s)), 0)) == ReturnCode_t::RETCODE_OK;
  if (writer.matched() == 0) {
    spdlog::error("no arbiter received the acknowledgement within {} s", timeout_s);
    return kExitFailure;
  }
  spdlog::info("acknowledged {} on {} of {} ({} readers{})", fault, component, turbine, writer.matched(),
               acked ? "" : ", not all confirmed");
  return kExitOk;
}

int print_history(const std::string& db, const std::string& turbine, double since, bool json) {
  FarmStore store(db);
  for (const auto& row : store.history(turbine, since)) {
    if (json) {
      std::cout
          << nlohmann::json{{"received_at", row.received_at}, {"kind", row.kind}, {"data", row.data}}.dump()
          << "\n";
      continue;
    }
    char when[32];
    const std::time_t secs = static_cast<std::time_t>(row.received_at);
    std::strftime(when, sizeof when, "%Y-%m-%d %H:%M:%S", std::gmtime(&secs));
    std::cout << when << "  " << row.kind << "  " << row.turbine_id << "  ";
    const auto& d = row.data;
    if (row.kind == "fault") {
      std::cout << d["component"].get<std::string>() << " " << d["fault"].get<std::string>() << " "
                << d["state"].get<std::string>() << " (" << d["severity"].get<std::string>() << ", from "
                << d["source"].get<std::string>() << ")";
    } else if (row.kind == "config") {
      std::cout << "r" << d["revision"] << " mode " << d["mode"].get<std::string>() << ", ipc "
                << d["ipc_source"].get<std::string>() << ", ice " << d["ice_mode"].get<std::string>();
    } else {
      std::cout << d["service"].get<std::string>() << " " << d["event"].get<std::string>();
    }
    std::cout << "\n";
  }
  return kExitOk;
}

}  // namespace windfdi::farm

namespace windfdi::farm {

int print_report(const std::string& db, const std::string& scenario, double since,
                 const std::string& history_file, bool json) {
  const auto history =
      history_file.empty() ? FarmStore(db).history("", since) : read_history_jsonl(history_file);
  const auto rows = match(read_injected(scenario), history);
  if (json) {
    std::cout << report_json(rows, history).dump() << "\n";
    return kExitOk;
  }
  std::cout << render_report(rows, history) << "\n" << render_benchmark_table(rows, history);
  return kExitOk;
}

}  // namespace windfdi::farm
