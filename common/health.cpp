// ServiceHealth publishing (1 Hz per served turbine).
#include "health.hpp"

#include <spdlog/spdlog.h>

#include "turbine_selection.hpp"

namespace windfdi {

HealthReporter::HealthReporter(bus::Participant& participant, std::string service,
                               std::vector<std::string> turbines)
    : writer_(participant), service_(std::move(service)) {
  // A range's turbines are reported as they are seen, as a farm-wide instance's are.
  turbines = TurbineSelection(turbines).ids();
  if (turbines.empty()) turbines.push_back("*");
  for (const auto& t : turbines) counters_[t];
}

HealthReporter::Counters& HealthReporter::entry(const std::string& turbine) {
  auto it = counters_.find(turbine);
  if (it != counters_.end()) return it->second;
  // The first real turbine replaces the "*" placeholder of a farm-wide instance. Its last sample leaves the
  // writer's history too: kept there (depth 1 per instance) it stayed the oldest while every turbine's
  // report moved on, and each periodic heartbeat then carried a GAP over every report since, which every
  // reader walked number by number (the arbiters' CPU grew by 60 % in 25 min of a 20-turbine soak).
  if (counters_.erase("*")) {
    windfdi::ServiceHealth placeholder;
    placeholder.turbine_id("*");
    placeholder.service(service_);
    writer_.unregister(placeholder);
  }
  return counters_[turbine];
}

void HealthReporter::set_state(windfdi::ServiceState state, const std::string& detail) {
  const bool changed = state != state_ || detail != detail_;
  state_ = state;
  detail_ = detail;
  if (changed) last_report_ = -1e300;  // report a change at the next tick
}

uint64_t HealthReporter::total_rejected() const {
  uint64_t n = 0;
  for (const auto& kv : counters_) n += kv.second.samples_rejected;
  return n;
}

void HealthReporter::report_refusals(const TurbineLimit& limit, double wall_now) {
  if (limit.refused() == refusals_reported_ || !due(wall_now)) return;
  refusals_reported_ = limit.refused();
  set_state(windfdi::SERVICE_OK, limit.describe());
}

void HealthReporter::tick(double wall_now, bool force) {
  writer_.assert_liveliness();
  if (!force && wall_now - last_report_ < 1.0) return;
  last_report_ = wall_now;
  for (const auto& [turbine, c] : counters_) {
    windfdi::ServiceHealth h;
    h.t(wall_now);
    h.turbine_id(turbine);
    h.service(service_);
    h.state(state_);
    h.samples_in(c.samples_in);
    h.samples_rejected(c.samples_rejected);
    h.sequence_gaps(c.sequence_gaps);
    h.lag(c.lag);
    h.deadlines_missed(streams_.deadlines_missed);
    h.samples_lost(streams_.samples_lost);
    h.incompatible_qos(streams_.incompatible_qos);
    h.detail(detail_);
    if (!writer_.write(h)) spdlog::warn("health report for {} not written (DDS resource limits?)", turbine);
  }
}

}  // namespace windfdi
