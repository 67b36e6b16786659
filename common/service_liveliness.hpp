// Which diagnostic services are alive for which turbine, from wt/health samples and writer liveliness.
#pragma once

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
class ServiceLiveliness {
 public:
  using Writer = eprosima::fastrtps::rtps::InstanceHandle_t;

  /// Takes new health samples and liveliness events; returns the appearances and losses, in order.
  /// `samples` receives the health samples taken (for callers that also want their contents).
  std::vector<ServiceChange> poll(bus::Reader<windfdi::ServiceHealth>& reader,
                                  std::vector<windfdi::ServiceHealth>* samples = nullptr);

  /// A health sample from `writer`: an appearance when no other live writer speaks for (turbine, service).
  void on_health(const Writer& writer, const std::string& turbine_id, const std::string& service,
                 std::vector<ServiceChange>& changes);
  /// `writer` lost its liveliness: a loss for each (turbine, service) no other live writer speaks for.
  void on_writer_lost(const Writer& writer, std::vector<ServiceChange>& changes);

 private:
  using Key = std::pair<std::string, std::string>;  // (turbine, service)
  std::map<Writer, std::set<Key>> writers_;
  std::map<Key, int> live_writers_;  // how many of writers_ speak for it
};

}  // namespace windfdi
