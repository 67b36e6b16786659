// Injected faults against what reached the farm monitor.
#include "fault_report.hpp"

#include <cstdio>
#include <sstream>

#include "yaml_config.hpp"

namespace windfdi::farm {

std::pair<std::string, std::string> expected_detection(const std::string& target, const std::string& type) {
  auto ends = [&](const char* p) { return target.rfind(p, 0) == 0 ? target.substr(std::string(p).size()) : ""; };
  if (type == "invalid") {
    if (!ends("blade_moment_").empty()) return {"blade_moment_sensor_" + ends("blade_moment_"), "sensor_invalid"};
    if (target == "lidar" || target.rfind("lidar_v_", 0) == 0) return {"lidar", "sensor_invalid"};
  }
  if (!ends("blade_moment_").empty()) {
    const std::string c = "blade_moment_sensor_" + ends("blade_moment_");
    if (type == "drift") return {c, "sensor_drift"};
    if (type == "intermittent") return {c, "sensor_intermittent"};
    return {c, "sensor_abrupt"};
  }
  if (target == "rotor_speed") return {"rotor_speed_sensor", "sensor_bias"};
  if (target == "generator_speed") return {"generator_speed_sensor", "sensor_bias"};
  if (!ends("pitch_").empty() && target.rfind("pitch_actuator_", 0) != 0) return {"pitch_sensor_" + ends("pitch_"), "sensor_bias"};
  if (target.rfind("pitch_actuator_", 0) == 0) return {target, type};
  if (target == "rotor") return {"rotor", type};
  return {"", ""};  // converter, drive train, anemometer, ...: no windfdi service covers them yet
}

std::vector<InjectedFault> read_injected(const std::string& file) {
  const auto root = YamlSection::load_file(file);
  std::vector<InjectedFault> out;
  for (const auto& f : root.sequence("faults")) {
    InjectedFault i;
    i.turbine = f.require<std::string>("turbine");
    i.target = f.require<std::string>("target");
    i.type = f.require<std::string>("type");
    i.start = f.require_number("start", 0.0, 1e9);
    std::tie(i.component, i.fault) = expected_detection(i.target, i.type);
    out.push_back(i);
  }
  return out;
}

std::vector<ReportRow> match(const std::vector<InjectedFault>& injected, const std::vector<HistoryRow>& history) {
  std::vector<ReportRow> rows;
  for (const auto& inj : injected) {
    ReportRow r;
    r.injected = inj;
    double received = 0.0;
    for (const auto& h : history) {
      if (h.kind != "fault" || h.turbine_id != inj.turbine) continue;
      const auto& d = h.data;
      if (d["component"] != inj.component || d["state"] != "raised") continue;
      const double td = d["t_detected"].is_number() ? d["t_detected"].get<double>() : d["t"].get<double>();
      if (td < inj.start) continue;
      const std::string fault = d["fault"].get<std::string>();
      if (r.detected) {
        const std::string& last = r.reclassified.empty() ? r.detected_fault : r.reclassified.back();
        if (fault != last) r.reclassified.push_back(fault);
        continue;
      }
      r.detected = true;
      r.detected_fault = fault;
      r.delay = td - inj.start;
      received = h.received_at;
    }
    if (r.detected)
      for (const auto& h : history)
        if (h.kind == "config" && h.turbine_id == inj.turbine && h.received_at >= received) {
          const auto& d = h.data;
          r.reaction = "mode " + d["mode"].get<std::string>() + ", ipc " + d["ipc_source"].get<std::string>() +
                       ", ice " + d["ice_mode"].get<std::string>();
          break;
        }
    rows.push_back(r);
  }
  return rows;
}

std::string render_report(const std::vector<ReportRow>& rows, const std::vector<HistoryRow>& history) {
  std::ostringstream out;
  char line[512];
  std::snprintf(line, sizeof line, "%-6s %-36s %7s  %-42s %-40s %-8s %s\n", "TURB", "INJECTED", "START",
                "EXPECTED", "DETECTED (then)", "DELAY", "ARBITER REACTION");
  out << line;
  int expected = 0, found = 0, found_later = 0;
  for (const auto& r : rows) {
    const auto& i = r.injected;
    const std::string exp = i.component.empty() ? "(not covered)" : i.component + " " + i.fault;
    std::string det = "-", delay = "-";
    if (!i.component.empty()) ++expected;
    if (r.detected) {
      det = r.detected_fault + (r.detected_fault == i.fault ? "" : " (!)");
      char d[32];
      std::snprintf(d, sizeof d, "%.1f s", r.delay);
      delay = d;
      found += r.detected_fault == i.fault;
      for (const auto& c : r.reclassified) det += " > " + c;
      found_later += r.detected_fault != i.fault && !r.reclassified.empty() && r.reclassified.back() == i.fault;
    } else if (!i.component.empty()) {
      det = "MISSED";
    }
    std::snprintf(line, sizeof line, "%-6s %-36s %6.0fs  %-42s %-40s %-8s %s\n", i.turbine.c_str(),
                  (i.target + ":" + i.type).c_str(), i.start, exp.c_str(), det.c_str(), delay.c_str(),
                  r.reaction.empty() ? "-" : r.reaction.c_str());
    out << line;
  }
  int unexpected = 0;
  for (const auto& h : history) {
    if (h.kind != "fault" || h.data["state"] != "raised") continue;
    bool explained = false;
    for (const auto& r : rows)
      explained |= r.injected.turbine == h.turbine_id && r.injected.component == h.data["component"];
    if (!explained) {
      ++unexpected;
      out << "unexpected: " << h.turbine_id << " " << h.data["component"].get<std::string>() << " "
          << h.data["fault"].get<std::string>() << " from " << h.data["source"].get<std::string>() << "\n";
    }
  }
  out << found << " of " << expected << " covered faults detected with the right class first";
  if (found_later > 0) out << ", " << found_later << " more after a re-classification";
  out << "; " << unexpected << " unexpected fault report(s)\n";
  return out.str();
}

}  // namespace windfdi::farm
