// The farm monitor's DDS node: faults, configurations and health of every turbine in; SQLite and a live
// table out. The one-shot subcommands (ack, history, report) are in farm_cli.hpp.
#pragma once

#include <map>
#include <memory>
#include <string>

#include "ControlConfiguration.h"
#include "FaultAck.h"
#include "FaultReport.h"
#include "ServiceHealth.h"
#include "app.hpp"
#include "blade_load_estimate_topic.hpp"
#include "dds/endpoints.hpp"
#include "drive_train_estimate_topic.hpp"
#include "farm_api.hpp"
#include "farm_http.hpp"
#include "farm_state.hpp"
#include "farm_store.hpp"
#include "health.hpp"
#include "ice_detect_estimate_topic.hpp"
#include "pitch_diag_estimate_topic.hpp"
#include "sensor_bias_estimate_topic.hpp"
#include "service_liveliness.hpp"
#include "store_backlog.hpp"
#include "turbine_limit.hpp"

namespace windfdi::farm {

struct FarmOptions {
  std::string db = "windfdi-farm.sqlite";  ///< SQLite database file
  double table_period = 1.0;               ///< s between live tables (0: no table)
  HttpOptions http;                        ///< the web page and API (off unless http.listen is set)
  double estimate_period = 1.0;            ///< s of estimate time between stored estimates (0: none stored)
  double estimate_retention = 24.0;        ///< h an estimate is kept
  std::string report_scenario;             ///< the plant scenario run, for the page's report ("" none)
};

ConfigRecord to_record(const windfdi::ControlConfiguration& c, double received_at);

class FarmNode {
 public:
  FarmNode(const CommonOptions& common, const FarmOptions& options);
  void run();

 private:
  void handle(double now);
  void store_estimates(double now);
  // Keeps `fields` when its service's last stored estimate of that turbine is estimate_period old.
  void sample(const std::string& turbine, const std::string& service, double t, nlohmann::json fields,
              double now);
  int publish_ack(const std::string& turbine, const std::string& component, const std::string& fault,
                  const std::string& operator_name);

  void on_stored(const StoreBacklog::Record& record);
  void keep_store_health(double now);

  FarmOptions options_;
  FarmStore store_;
  StoreBacklog backlog_;
  FarmState state_;
  bus::Participant participant_;
  bus::Wakeup wakeup_;
  bus::Reader<windfdi::FaultReport> faults_;
  bus::Reader<windfdi::ControlConfiguration> configs_;
  bus::Reader<windfdi::ServiceHealth> health_;
  bus::Reader<windfdi::BladeLoadEstimate> blade_estimates_;
  bus::Reader<windfdi::SensorBiasEstimate> bias_estimates_;
  bus::Reader<windfdi::PitchActuatorEstimate> pitch_estimates_;
  bus::Reader<windfdi::InertiaEstimate> inertia_estimates_;
  bus::Reader<windfdi::DriveTrainEstimate> drive_train_estimates_;
  std::map<std::string, double> estimate_stored_at_;  // turbine/service -> t of the last stored estimate
  std::vector<EstimateRecord> estimate_batch_;
  double pruned_at_ = 0.0;
  // s between prunings of the old estimates: each deletes a few seconds' worth (about 40 ms of a core with
  // 20 turbines at 10x); once a minute deleted a minute's worth in one transaction, a spike the soak's
  // services lost samples to.
  static constexpr double kPrunePeriod = 5.0;
  // Every map here and the store hold admitted turbines only (a hostile peer names any number).
  TurbineLimit limit_;
  ForeignReports foreign_reports_;
  std::string refused_note_;  ///< limit_.describe() as last said in the health detail
  ServiceLiveliness liveliness_;
  std::map<std::string, ServiceMetrics>
      metrics_;  // turbine/service -> its last health (state stored, /metrics)
  // The farm monitor's own health (service "farm_monitor", turbine "*"): degraded while its store fails.
  // Absent when the security grants predate it (the log and /metrics still say it).
  std::unique_ptr<HealthReporter> self_health_;
  uint64_t dropped_logged_ = 0;
  // The web side (with --http): destroyed first, so no request reaches a node being torn down.
  std::unique_ptr<bus::Writer<windfdi::FaultAck>> acks_;
  std::unique_ptr<FarmApi> api_;
  std::unique_ptr<FarmHttp> http_;
};

}  // namespace windfdi::farm
