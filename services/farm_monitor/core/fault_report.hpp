// Injected faults (a plant scenario) against what reached the farm monitor: component, class, delay.
#pragma once

#include <string>
#include <vector>

#include "farm_store.hpp"

namespace windfdi::farm {

struct InjectedFault {
  std::string turbine, target, type;
  double start = 0.0;
  std::string component, fault;  ///< what a diagnostic service should report ("" when none covers it)
};

struct ReportRow {
  InjectedFault injected;
  bool detected = false;
  std::string detected_fault;  ///< the class reported on the component first after the start
  std::vector<std::string> reclassified;  ///< classes raised on it later, in order (a service changing its mind)
  double delay = 0.0;          ///< s of measurement time from the start to t_detected
  std::string reaction;        ///< the arbiter's first configuration change after detection
};

/// The component and class a service should report for a plant fault (target, type); empty when none.
std::pair<std::string, std::string> expected_detection(const std::string& target, const std::string& type);
/// Reads the faults of a plant scenario (only what the report needs).
std::vector<InjectedFault> read_injected(const std::string& scenario_file);
/// Matches each injected fault with the first raised report on its component at or after its start.
std::vector<ReportRow> match(const std::vector<InjectedFault>& injected, const std::vector<HistoryRow>& history);
std::string render_report(const std::vector<ReportRow>& rows, const std::vector<HistoryRow>& history);

}  // namespace windfdi::farm
