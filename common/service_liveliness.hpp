// Which diagnostic services are alive for which turbine, from wt/health samples and writer liveliness.
#pragma once

#include <deque>
#include <functional>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "ServiceHealth.h"
#include "dds/endpoints.hpp"

namespace windfdi {

/// A service appearing for a turbine, or losing its liveliness ("*" as turbine: every turbine).
struct ServiceChange {
  std::string turbine_id;
  std::string service;
  bool alive;
};

/// Feeds on a ServiceHealth reader; remembers which writers speak for which (turbine, service). A service
/// is alive while one of its writers is: a service restarted by systemd has a new writer, often seen before
/// the old one's lease runs out, and that old writer's loss must not declare the running service lost.
///
/// A lost writer's turbines are remembered: when its liveliness comes back (a process thawed after a stall, a
/// network healed) they are alive again at once, not at its next health sample. That sample is reliable, and
/// after a stall it may wait seconds for a lost predecessor to be repaired: a thawed arbiter kept sensor_bias
/// lost for 8 s after the service's liveliness was back.
///
/// "*" is the placeholder of an instance that has not seen a turbine yet, and speaks for the turbines no
/// writer of that service has named. Once a writer names a real turbine it no longer speaks for "*" (it is
/// narrowed, not lost): two instances sharing a farm's turbines (one per host) would otherwise each hold the
/// other's turbines alive, or a dead one's "*" would take the other's turbines with it.
class ServiceLiveliness {
 public:
  using Writer = eprosima::fastrtps::rtps::InstanceHandle_t;

  /// Takes new health samples and liveliness events; returns the appearances and losses, in order.
  /// `samples` receives the health samples taken (for callers that also want their contents).
  /// `admit`, when given, decides which samples count at all (the others are dropped, also from `samples`):
  /// every (turbine, service) named is remembered, so a caller bounds them (TurbineLimit, is_health_source).
  std::vector<ServiceChange> poll(bus::Reader<windfdi::ServiceHealth>& reader,
                                  std::vector<windfdi::ServiceHealth>* samples = nullptr,
                                  const std::function<bool(const windfdi::ServiceHealth&)>& admit = {});

  /// A health sample from `writer`: an appearance when no other live writer speaks for (turbine, service).
  void on_health(const Writer& writer, const std::string& turbine_id, const std::string& service,
                 std::vector<ServiceChange>& changes);
  /// `writer` lost its liveliness: a loss for each (turbine, service) no other live writer speaks for.
  void on_writer_lost(const Writer& writer, std::vector<ServiceChange>& changes);
  /// `writer` regained its liveliness: an appearance for each (turbine, service) it spoke for when it was
  /// lost and no other live writer speaks for. Nothing for a writer never seen or not lost.
  void on_writer_alive(const Writer& writer, std::vector<ServiceChange>& changes);

  /// Whether a live writer speaks for `service` on `turbine_id`: one that named it, or, for a turbine no
  /// writer has named, one of "*". A change of "*" (appearance or loss) applies to the turbines where this
  /// gives the new state.
  bool alive(const std::string& turbine_id, const std::string& service) const;
  /// Whether a writer (live or lost) has named `turbine_id` for `service`.
  bool named(const std::string& turbine_id, const std::string& service) const {
    return live_writers_.count({turbine_id, service}) > 0;
  }

 private:
  using Key = std::pair<std::string, std::string>;  // (turbine, service)
  std::map<Writer, std::set<Key>> writers_;
  std::map<Key, int> live_writers_;  // how many of writers_ speak for it; kept at 0 once named
  // Lost writers and what they spoke for, oldest first out: a killed service's writer never comes back, so
  // at most kLostWritersKept (every restart of every service of a large farm for a long while) are kept.
  static constexpr std::size_t kLostWritersKept = 1024;
  std::map<Writer, std::set<Key>> lost_writers_;
  std::deque<Writer> lost_order_;
};

}  // namespace windfdi
