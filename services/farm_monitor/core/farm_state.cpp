// The farm monitor's live picture.
#include "farm_state.hpp"

#include <algorithm>
#include <cstdio>
#include <sstream>

namespace windfdi::farm {

void FarmState::on_fault(const FaultEvent& e) {
  turbines_[e.turbine_id].faults[e.component + "/" + e.fault] = e;
}

void FarmState::on_config(const ConfigRecord& c) {
  auto& t = turbines_[c.turbine_id];
  t.mode = c.mode;
  t.ipc_source = c.ipc_source;
  t.ice_mode = c.ice_mode;
  t.revision = c.revision;
  t.arbiter_id = c.arbiter_id;
}

void FarmState::on_service(const std::string& turbine_id, const std::string& service,
                           const std::string& state) {
  if (turbine_id == "*") {
    for (auto& [id, t] : turbines_) t.services[service] = state;
    return;
  }
  turbines_[turbine_id].services[service] = state;
}

void FarmState::on_service_lost(const std::string& turbine_id, const std::string& service) {
  on_service(turbine_id, service, "lost");
}

std::vector<ActiveFault> FarmState::raised(const std::string& turbine_id) const {
  std::vector<ActiveFault> out;
  const auto it = turbines_.find(turbine_id);
  if (it == turbines_.end()) return out;
  // The same isolation as the arbiter's: a report another one explains is secondary.
  std::vector<isolation::Report> reports;
  for (const auto& [key, e] : it->second.faults)
    if (e.raised) {
      out.push_back({&e, {}});
      reports.push_back({e.source, e.component, e.fault, e.t_detected});
    }
  const auto verdicts = isolation::isolate(reports);
  for (std::size_t i = 0; i < out.size(); ++i) out[i].verdict = verdicts[i];
  return out;
}

std::vector<std::string> FarmState::active_faults(const std::string& turbine_id) const {
  std::vector<std::string> out;
  const auto it = turbines_.find(turbine_id);
  if (it == turbines_.end()) return out;
  for (const auto& [e, verdict] : raised(turbine_id))
    out.push_back(e->component + " " + e->fault + " (" + e->severity + ")" +
                  (verdict.secondary ? ", secondary: explained by " + verdict.explained_by : ""));
  for (const auto& [service, state] : it->second.services)
    if (state == "lost") out.push_back(service + " service_lost");
  return out;
}

std::string FarmState::render() const {
  std::ostringstream out;
  char line[512];
  std::snprintf(line, sizeof line, "%-10s %-10s %-13s %-8s %-36s %s\n", "TURBINE", "MODE", "IPC", "ICE",
                "SERVICES", "ACTIVE FAULTS");
  out << line;
  for (const auto& [id, t] : turbines_) {
    // Six services do not fit a column by name: count the healthy ones, name the others.
    int ok = 0;
    std::string others;
    for (const auto& [name, state] : t.services) {
      if (state == "ok")
        ++ok;
      else
        others += " " + name + ":" + state;
    }
    const std::string services = std::to_string(ok) + " ok" + others;
    const auto faults = active_faults(id);
    std::string first = faults.empty() ? "-" : faults.front();
    std::snprintf(line, sizeof line, "%-10s %-10s %-13s %-8s %-36s %s\n", id.c_str(), t.mode.c_str(),
                  t.ipc_source.c_str(), t.ice_mode.c_str(), services.substr(0, 36).c_str(), first.c_str());
    out << line;
    for (std::size_t i = 1; i < faults.size(); ++i) {
      std::snprintf(line, sizeof line, "%-81s %s\n", "", faults[i].c_str());
      out << line;
    }
  }
  return out.str();
}

}  // namespace windfdi::farm
