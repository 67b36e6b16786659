// A fault event as the diagnostic cores produce it (plain C++), and its JSON Lines form.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace windfdi {

/// One raised or cleared fault of one component, in the canonical names of docs/architecture.md.
struct FaultEvent {
  double t = 0.0;  ///< time of this report (s, measurement time)
  std::string turbine_id;
  std::string source;              ///< service name, e.g. "pitch_diag"
  std::string component;           ///< e.g. "pitch_actuator_2"
  std::string fault;               ///< canonical fault class, e.g. "hydraulic_leakage"
  bool raised = true;              ///< false: cleared
  std::string severity = "fault";  ///< info, warning, fault or critical
  double t_detected = 0.0;         ///< when the fault was first detected (s)
  double statistic = 0.0;          ///< the test statistic that decided
  double threshold = 0.0;          ///< what the statistic was compared with
  double size = 0.0;               ///< estimated fault size, in the channel's unit
  std::string detail;
};

/// The longest detail kept of a FaultReport received on DDS (bytes); a longer one is cut (the IDL's strings
/// are unbounded, and a peer on an unsecured domain may send megabytes).
constexpr std::size_t kMaxReportDetail = 4096;

/// Why a FaultReport received on DDS is none windfdi's services could have sent ("" when it could): its
/// source is no diagnostic service, its component or class is not canonical or not of that component, or its
/// severity is unknown. Such a report is counted and dropped, never kept: its strings could be anything.
std::string foreign_report_reason(const FaultEvent& e);

/// The replay contract's event line: keys t, turbine_id, source, component, fault, state, severity,
/// statistic, detail (plus threshold, size and t_detected).
nlohmann::json to_json(const FaultEvent& e);
FaultEvent fault_event_from_json(const nlohmann::json& j);

}  // namespace windfdi
