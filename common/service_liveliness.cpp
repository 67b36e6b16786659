// Which diagnostic services are alive for which turbine.
#include "service_liveliness.hpp"

namespace windfdi {

std::vector<ServiceChange> ServiceLiveliness::poll(bus::Reader<windfdi::ServiceHealth>& reader,
                                                   std::vector<windfdi::ServiceHealth>* samples) {
  std::vector<ServiceChange> changes;
  std::vector<windfdi::ServiceHealth> health;
  std::vector<bus::SampleMeta> meta;
  reader.take(health, &meta);
  for (std::size_t i = 0; i < health.size(); ++i) {
    auto& known = writers_[meta[i].writer];
    if (!known.count(health[i].turbine_id()))
      changes.push_back({health[i].turbine_id(), health[i].service(), true});
    known[health[i].turbine_id()] = health[i].service();
  }
  for (const auto& ev : reader.take_liveliness_events()) {
    if (ev.alive) continue;
    auto it = writers_.find(ev.writer);
    if (it == writers_.end()) continue;
    for (const auto& [turbine, service] : it->second) changes.push_back({turbine, service, false});
    writers_.erase(it);
  }
  if (samples) *samples = std::move(health);
  return changes;
}

}  // namespace windfdi
