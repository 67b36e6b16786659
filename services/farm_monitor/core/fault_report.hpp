// Injected faults (a plant scenario) against what reached the farm monitor: component, class, delay.
#pragma once

#include <string>
#include <vector>

#include "farm_store.hpp"
#include "turbine_params.hpp"

namespace windfdi::farm {

struct InjectedFault {
  std::string turbine, target, type;
  double start = 0.0;
  std::string component, fault;  ///< what a diagnostic service should report ("" when none covers it)
  double end = 1e300;            ///< s, when it stops acting (end, or start + ramp_in + hold, plus ramp_out)
  double value = 0.0;            ///< the scenario's value (an ice mass decides whether it warrants a stop)
  double ramp_in = 0.0;          ///< s (ice accretion: the mass grows over it)
  double fraction = 1.0;         ///< ice shedding: the share of the ice that falls off
  double stop_ice_mass =
      4500.0;  ///< kg of ice that warrants a stop on this scenario's turbine (stop_ice_mass())
};

/// The ice (kg) that warrants a stop on a turbine: ice_detect's shipped critical level, 12.3 % of the clean
/// inertia (deploy/config/ice_detect.yaml critical_rise), with the ice at the turbine file's ice_radius. 4500
/// kg on the benchmark rotor.
double stop_ice_mass(const TurbineParams& turbine);

/// The ice on a turbine's rotor at time t (kg) as the plant accounts it: accretions add their mass over
/// their ramp, a shedding drops its fraction of what is there.
double injected_ice(const std::vector<InjectedFault>& injected, const std::string& turbine, double t);

struct ReportRow {
  InjectedFault injected;
  bool detected = false;
  std::string detected_fault;  ///< the class reported on the component first after the start
  std::vector<std::string>
      reclassified;      ///< classes raised on it later, in order (a service changing its mind)
  double delay = 0.0;    ///< s of measurement time from the start to t_detected
  std::string reaction;  ///< the arbiter's first configuration change after detection
  bool detected_while_active =
      false;  ///< the first detection came before the fault ended (the benchmark's test)
};

/// A raised report that no injected fault explains, or one the isolation core explains by another report.
struct ExtraReport {
  std::string turbine, component, fault, source;
  double t_detected = 0.0;
  bool secondary = false;
  std::string explained_by;  ///< "component class" of the root, or the common cause
};

/// A safe stop the arbiter commanded, and whether an injected fault of a stopping class warranted it.
struct StopRecord {
  std::string turbine;
  double t = 0.0;  ///< s, turbine time of the configuration
  bool warranted = false;
};

/// The component and class a service should report for a plant fault (target, type); empty when none.
std::pair<std::string, std::string> expected_detection(const std::string& target, const std::string& type);
/// Reads the faults of a plant scenario (only what the report needs).
std::vector<InjectedFault> read_injected(const std::string& scenario_file);
/// Matches each injected fault with the first raised report on its component at or after its start.
std::vector<ReportRow> match(const std::vector<InjectedFault>& injected,
                             const std::vector<HistoryRow>& history);
/// Raised reports outside every injected fault's window, each isolated against the turbine's other reports.
std::vector<ExtraReport> extra_reports(const std::vector<InjectedFault>& injected,
                                       const std::vector<HistoryRow>& history);
/// Each change to safe stop, judged against the injected faults that warrant one: a hydraulic leak active, or
/// ended within 300 s, at that time; ice on the rotor within 10 % of ice_detect's critical 4500 kg at some
/// time in the 120 s before it.
std::vector<StopRecord> stops(const std::vector<InjectedFault>& injected,
                              const std::vector<HistoryRow>& history);
/// The table of injected faults against detections, then the reports no injected fault explains (secondary
/// ones apart, with their root), the safe stops, and a summary.
std::string render_report(const std::vector<ReportRow>& rows, const std::vector<HistoryRow>& history);
/// The FDI/FTC benchmark's own table: per fault, detected and isolated while active, delay in s and in
/// samples (100 Hz), and the false alarms (unexpected root reports) of the run.
std::string render_benchmark_table(const std::vector<ReportRow>& rows,
                                   const std::vector<HistoryRow>& history);
/// The same as JSON (rows, extra reports, stops), for the multi-fault suite's aggregation.
nlohmann::json report_json(const std::vector<ReportRow>& rows, const std::vector<HistoryRow>& history);
/// History rows from `windfdi-farm history --json` lines (what system_replay writes too).
std::vector<HistoryRow> read_history_jsonl(const std::string& file);

}  // namespace windfdi::farm
