// Which diagnostic services are alive for which turbine.
#include "service_liveliness.hpp"

namespace windfdi {

void ServiceLiveliness::on_health(const Writer& writer, const std::string& turbine_id,
                                  const std::string& service, std::vector<ServiceChange>& changes) {
  const Key key{turbine_id, service}, placeholder{"*", service};
  auto& keys = writers_[writer];
  if (turbine_id == "*") {
    // A writer that has spoken for a real turbine of this service no longer speaks for every turbine.
    for (const auto& k : keys)
      if (k.second == service && k.first != "*") return;
  } else if (keys.erase(placeholder)) {
    // Narrowed, not lost: its real turbines speak for it from now on.
    --live_writers_[placeholder];
  }
  if (!keys.insert(key).second) return;
  if (live_writers_[key]++ == 0) changes.push_back({turbine_id, service, true});
}

bool ServiceLiveliness::alive(const std::string& turbine_id, const std::string& service) const {
  auto it = live_writers_.find({turbine_id, service});
  if (it == live_writers_.end()) it = live_writers_.find({"*", service});
  return it != live_writers_.end() && it->second > 0;
}

void ServiceLiveliness::on_writer_lost(const Writer& writer, std::vector<ServiceChange>& changes) {
  auto it = writers_.find(writer);
  if (it == writers_.end()) return;
  for (const auto& key : it->second)
    if (--live_writers_[key] == 0) changes.push_back({key.first, key.second, false});
  writers_.erase(it);
}

std::vector<ServiceChange> ServiceLiveliness::poll(
    bus::Reader<windfdi::ServiceHealth>& reader, std::vector<windfdi::ServiceHealth>* samples,
    const std::function<bool(const windfdi::ServiceHealth&)>& admit) {
  std::vector<ServiceChange> changes;
  std::vector<windfdi::ServiceHealth> health, admitted;
  std::vector<bus::SampleMeta> meta;
  reader.take(health, &meta);
  for (std::size_t i = 0; i < health.size(); ++i) {
    if (admit && !admit(health[i])) continue;
    on_health(meta[i].writer, health[i].turbine_id(), health[i].service(), changes);
    admitted.push_back(std::move(health[i]));
  }
  for (const auto& ev : reader.take_liveliness_events())
    if (!ev.alive) on_writer_lost(ev.writer, changes);
  if (samples) *samples = std::move(admitted);
  return changes;
}

}  // namespace windfdi
