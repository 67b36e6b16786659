// The farm monitor's durable event store: SQLite in WAL mode, one row per distinct event, so a restart
// that replays transient-local samples adds nothing twice.
#pragma once

#include <sqlite3.h>

#include <optional>
#include <string>
#include <vector>

#include "fault_event.hpp"

namespace windfdi::farm {

/// A control configuration as the farm monitor records it.
struct ConfigRecord {
  double received_at = 0.0;  ///< wall time (s since the Unix epoch)
  double t = 0.0;            ///< arbiter's time stamp
  std::string turbine_id;
  std::string arbiter_id;
  uint64_t revision = 0;
  std::string mode, ipc_source, ice_mode;
  std::vector<std::string> reasons;  ///< "source/component/fault: action"
};

/// A service's health change (alive, lost, state change).
struct HealthRecord {
  double received_at = 0.0;
  std::string turbine_id;
  std::string service;
  std::string event;  ///< "alive", "lost", or the ServiceState name
  std::string detail;
};

/// A diagnostic service's estimate for one turbine, as stored (at most one per second per service and
/// turbine): its fields by name, an array per blade ({"omega_n": [w1, w2, w3], "excited": [...]}).
struct EstimateRecord {
  double received_at = 0.0;  ///< wall time
  double t = 0.0;            ///< the estimate's own time stamp
  std::string turbine_id;
  std::string service;
  nlohmann::json fields;
};

/// One row of the history, whatever its kind.
struct HistoryRow {
  double received_at = 0.0;
  std::string kind;  ///< "fault", "config" or "health"
  std::string turbine_id;
  nlohmann::json data;
};

class FarmStore {
 public:
  /// Opens (creating if needed) the database; throws ConfigError when it cannot.
  explicit FarmStore(const std::string& path);
  ~FarmStore();
  FarmStore(const FarmStore&) = delete;
  FarmStore& operator=(const FarmStore&) = delete;

  /// Each returns true when the row is new (false: already stored, e.g. replayed after a restart).
  bool add_fault(const FaultEvent& e, double received_at);
  bool add_config(const ConfigRecord& c);
  bool add_health(const HealthRecord& h);

  /// Stores a batch of estimates in one transaction (an estimate already stored is skipped).
  void add_estimates(const std::vector<EstimateRecord>& batch);
  /// Deletes the estimates received before `before` (wall time); returns how many.
  int64_t prune_estimates(double before);
  /// The newest `limit` estimates of one service on one turbine received since `since`, oldest first.
  std::vector<EstimateRecord> estimates(const std::string& turbine, const std::string& service, double since,
                                        std::size_t limit) const;

  /// Every row since `since` (wall time), oldest first, for one turbine or all (empty).
  std::vector<HistoryRow> history(const std::string& turbine_id, double since) const;
  /// The latest stored state of every fault instance (turbine, source, component, fault).
  std::vector<FaultEvent> latest_faults() const;
  int64_t count(const std::string& table) const;

 private:
  void exec(const char* sql);
  void check_intact();  // throws ConfigError (exit 2) on a damaged store, leaving it as it is
  sqlite3* db_ = nullptr;
  std::string path_;
};

}  // namespace windfdi::farm
