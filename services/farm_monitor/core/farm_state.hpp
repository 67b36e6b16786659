// The farm monitor's live picture: per turbine, the arbiter's mode and every component's fault state.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "farm_store.hpp"
#include "fault_event.hpp"
#include "isolation.hpp"

namespace windfdi::farm {

struct TurbineView {
  std::string mode = "-", ipc_source = "-", ice_mode = "-", arbiter_id;
  uint64_t revision = 0;
  std::map<std::string, FaultEvent> faults;     ///< key component/fault: the latest report, raised or not
  std::map<std::string, std::string> services;  ///< service -> "ok", "lost", "degraded", ...
};

/// A raised report of a turbine with the isolation core's verdict on it (secondary: another report explains
/// it).
struct ActiveFault {
  const FaultEvent* event;
  isolation::Verdict verdict;
};

class FarmState {
 public:
  void on_fault(const FaultEvent& e);
  void on_config(const ConfigRecord& c);
  void on_service(const std::string& turbine_id, const std::string& service, const std::string& state);
  /// Marks `service` lost on every turbine it served ("*": all).
  void on_service_lost(const std::string& turbine_id, const std::string& service);

  const std::map<std::string, TurbineView>& turbines() const { return turbines_; }
  /// The raised reports of a turbine, each isolated against the others by the arbiter's core (pointers into
  /// this state: valid while it is not changed).
  std::vector<ActiveFault> raised(const std::string& turbine_id) const;
  /// The raised faults of a turbine, "component fault (severity)".
  std::vector<std::string> active_faults(const std::string& turbine_id) const;
  /// The table: one row per turbine with mode, IPC, ice, services and active faults.
  std::string render() const;

 private:
  std::map<std::string, TurbineView> turbines_;
};

}  // namespace windfdi::farm
