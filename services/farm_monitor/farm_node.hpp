// The farm monitor's DDS node: faults, configurations and health of every turbine in; SQLite and a live
// table out; operator acknowledgements published.
#pragma once

#include <string>

#include "ControlConfiguration.h"
#include "FaultAck.h"
#include "FaultReport.h"
#include "ServiceHealth.h"
#include "app.hpp"
#include "dds/endpoints.hpp"
#include "farm_state.hpp"
#include "farm_store.hpp"
#include "service_liveliness.hpp"

namespace windfdi::farm {

struct FarmOptions {
  std::string db = "windfdi-farm.sqlite";  ///< SQLite database file
  double table_period = 1.0;               ///< s between live tables (0: no table)
};

ConfigRecord to_record(const windfdi::ControlConfiguration& c, double received_at);

class FarmNode {
 public:
  FarmNode(const CommonOptions& common, const FarmOptions& options);
  void run();

 private:
  void handle(double now);

  FarmOptions options_;
  FarmStore store_;
  FarmState state_;
  bus::Participant participant_;
  bus::Wakeup wakeup_;
  bus::Reader<windfdi::FaultReport> faults_;
  bus::Reader<windfdi::ControlConfiguration> configs_;
  bus::Reader<windfdi::ServiceHealth> health_;
  ServiceLiveliness liveliness_;
  std::map<std::string, std::string> service_state_;  // turbine/service -> last state stored
};

/// Publishes one FaultAck and waits (up to `timeout_s`) for it to be acknowledged by the readers.
int publish_ack(const CommonOptions& common, const std::string& turbine, const std::string& component,
                const std::string& fault, const std::string& operator_name, double timeout_s);

/// Prints injected faults against detections (ends the demo).
/// `history_file` (JSON Lines of `history --json`) instead of the database when given.
/// `json`: one JSON object (faults, extra reports, stops) instead of the tables.
int print_report(const std::string& db, const std::string& scenario, double since,
                 const std::string& history_file, bool json);

/// Prints the stored history (a table, or JSON Lines with `json`).
int print_history(const std::string& db, const std::string& turbine, double since, bool json);

}  // namespace windfdi::farm
