// The farm monitor's DDS node: faults, configurations and health of every turbine in; SQLite and a live
// table out. The one-shot subcommands (ack, history, report) are in farm_cli.hpp.
#pragma once

#include <string>

#include "ControlConfiguration.h"
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

}  // namespace windfdi::farm
