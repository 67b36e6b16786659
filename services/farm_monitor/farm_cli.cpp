// The farm monitor's one-shot subcommands: ack (publish one FaultAck), history and report (from the store).
#include "farm_cli.hpp"

#include <spdlog/spdlog.h>

#include <cmath>
#include <ctime>
#include <iostream>

#include "FaultAck.h"
#include "dds/convert.hpp"
#include "dds/endpoints.hpp"
#include "farm_store.hpp"
#include "fault_report.hpp"
#include "names.hpp"
#include "yaml_config.hpp"

namespace windfdi::farm {

windfdi::FaultAck make_ack(const std::string& turbine, const std::string& component, const std::string& fault,
                           const std::string& operator_name, const std::string& key) {
  windfdi::FaultClass fc = windfdi::FAULT_NONE;
  if (!bus::fault_class_from_name(fault, fc))
    throw ConfigError(key, 0, "", "'" + fault + "' is not a fault class");
  if (!is_component(component)) throw ConfigError(key, 0, "", "'" + component + "' is not a component");
  windfdi::FaultAck ack;
  ack.t(wall_time());
  ack.turbine_id(turbine);
  ack.component(component);
  ack.fault_class(fc);
  ack.operator_name(operator_name);
  return ack;
}

int publish_ack(const CommonOptions& common, const std::string& turbine, const std::string& component,
                const std::string& fault, const std::string& operator_name, double timeout_s) {
  const windfdi::FaultAck ack = make_ack(turbine, component, fault, operator_name, "--fault or COMPONENT");
  bus::Participant participant(participant_options(common, "windfdi-farm-ack"));
  bus::Writer<windfdi::FaultAck> writer(participant);
  writer.wait_for_readers(1, std::chrono::milliseconds(static_cast<int>(timeout_s * 1000)));
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
