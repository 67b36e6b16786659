// ServiceHealth publishing (1 Hz per served turbine): samples in, samples rejected, sequence gaps, lag.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "ServiceHealth.h"
#include "dds/endpoints.hpp"
#include "turbine_limit.hpp"

namespace windfdi {

/// Counts per turbine and publishes them once a second; the writer's liveliness lease lets every reader
/// notice when this service dies. Called from the node's loop only (not thread-safe by design).
class HealthReporter {
 public:
  /// `turbines`: the ids this instance serves (empty: every turbine, reported as "*" until seen).
  HealthReporter(bus::Participant& participant, std::string service, std::vector<std::string> turbines);

  void count_in(const std::string& turbine, uint64_t n = 1) { entry(turbine).samples_in += n; }
  void count_rejected(const std::string& turbine, uint64_t n = 1) { entry(turbine).samples_rejected += n; }
  void count_gap(const std::string& turbine, uint64_t lost) { entry(turbine).sequence_gaps += lost; }
  void set_lag(const std::string& turbine, double seconds) { entry(turbine).lag = seconds; }
  void set_state(windfdi::ServiceState state, const std::string& detail = "");

  /// What DDS reports of the instance's streams since start (every turbine's report carries them): a missed
  /// deadline is an input stream gone silent, lost samples an overloaded reader, incompatible QoS a peer
  /// that will never be heard.
  struct StreamStatus {
    uint64_t deadlines_missed = 0, samples_lost = 0, incompatible_qos = 0;
  };
  void add_streams(const bus::EndpointStatus& e) {
    streams_.deadlines_missed += e.deadline_missed.load();
    streams_.samples_lost += e.samples_lost.load();
    streams_.incompatible_qos += e.incompatible_qos.load();
  }
  /// Sets the stream status to the sum over these readers and writers.
  template <class... Endpoints>
  void set_streams_of(const Endpoints&... endpoints) {
    streams_ = {};
    (add_streams(endpoints.status()), ...);
  }

  /// Whether the next tick at `wall_now` publishes (a second has passed since the last report).
  bool due(double wall_now) const { return wall_now - last_report_ >= 1.0; }
  /// Puts the limit's refusals in the detail (state OK) when they grew and a report is due, so a flood of
  /// made-up turbines shows in the health at most once a second.
  void report_refusals(const TurbineLimit& limit, double wall_now);
  /// Publishes when a second has passed since the last report (or `force`).
  void tick(double wall_now, bool force = false);
  uint64_t total_rejected() const;

 private:
  struct Counters {
    uint64_t samples_in = 0, samples_rejected = 0, sequence_gaps = 0;
    double lag = 0.0;
  };
  Counters& entry(const std::string& turbine);

  bus::Writer<windfdi::ServiceHealth> writer_;
  std::string service_;
  std::map<std::string, Counters> counters_;
  windfdi::ServiceState state_ = windfdi::SERVICE_STARTING;
  std::string detail_;
  StreamStatus streams_;
  double last_report_ = -1e300;
  uint64_t refusals_reported_ = 0;
};

}  // namespace windfdi
