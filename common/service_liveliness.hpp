// Which diagnostic services are alive for which turbine, from wt/health samples and writer liveliness.
#pragma once

#include <map>
#include <string>
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

/// Feeds on a ServiceHealth reader; remembers which writer speaks for which (turbine, service) so that
/// a writer's lost liveliness names the services that died.
class ServiceLiveliness {
 public:
  /// Takes new health samples and liveliness events; returns the appearances and losses, in order.
  /// `samples` receives the health samples taken (for callers that also want their contents).
  std::vector<ServiceChange> poll(bus::Reader<windfdi::ServiceHealth>& reader,
                                  std::vector<windfdi::ServiceHealth>* samples = nullptr);

 private:
  std::map<eprosima::fastrtps::rtps::InstanceHandle_t, std::map<std::string, std::string>> writers_;
};

}  // namespace windfdi
