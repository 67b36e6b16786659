// Which diagnostic services are alive for which turbine.
#include "service_liveliness.hpp"

#include <algorithm>

namespace windfdi {

void ServiceLiveliness::on_health(const Writer& writer, const std::string& turbine_id,
                                  const std::string& service, std::vector<ServiceChange>& changes) {
  // A health sample is proof of life too: what the writer spoke for before its loss is alive again.
  on_writer_alive(writer, changes);
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
  if (lost_writers_.emplace(writer, std::move(it->second)).second) lost_order_.push_back(writer);
  writers_.erase(it);
  while (lost_order_.size() > kLostWritersKept) {
    lost_writers_.erase(lost_order_.front());
    lost_order_.pop_front();
  }
}

void ServiceLiveliness::on_writer_alive(const Writer& writer, std::vector<ServiceChange>& changes) {
  auto it = lost_writers_.find(writer);
  if (it == lost_writers_.end()) return;
  auto& keys = writers_[writer];
  for (const auto& key : it->second)
    if (keys.insert(key).second && live_writers_[key]++ == 0)
      changes.push_back({key.first, key.second, true});
  lost_writers_.erase(it);
  lost_order_.erase(std::find(lost_order_.begin(), lost_order_.end(), writer));
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
  for (const auto& ev : reader.take_liveliness_events()) {
    if (ev.alive)
      on_writer_alive(ev.writer, changes);
    else
      on_writer_lost(ev.writer, changes);
  }
  if (samples) *samples = std::move(admitted);
  return changes;
}

}  // namespace windfdi
