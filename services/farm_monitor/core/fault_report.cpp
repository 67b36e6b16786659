// Injected faults against what reached the farm monitor.
#include "fault_report.hpp"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>

#include "deploy_dir.hpp"
#include "isolation.hpp"
#include "yaml_config.hpp"

namespace windfdi::farm {

namespace {

// s after an injected fault ends during which reports on its component are still its own (a service's clear
// hysteresis, a re-classification at the end).
constexpr double kAfterEnd = 60.0;
// s after an injected shedding during which an ice_shedding report is still its own. A shedding is an instant
// with no end; without a limit every later false shedding on that rotor (the ice that stayed) counted as it.
// Five times the class's 60 s delay target: the late reports the suite measures stay the shedding's.
constexpr double kShedAttribution = 300.0;
// s a stop may follow the end of the fault that warranted it (confirmation, the configuration's way back).
constexpr double kStopAfterEnd = 300.0;
// Ice that warrants a stop: ice_detect's critical level (stop_ice_mass), less the estimator's error (rms 1 %
// of the inertia, about 400 kg on the benchmark rotor).
constexpr double kStopIceRise = 0.1230, kStopIceShare = 0.9, kStopIceWindow = 120.0;

double detected_at(const nlohmann::json& d) {
  return d["t_detected"].is_number() ? d["t_detected"].get<double>() : d["t"].get<double>();
}

// The last time a report can belong to an injected fault.
double attribution_end(const InjectedFault& i) {
  return i.type == "ice_shedding" ? i.start + kShedAttribution : i.end + kAfterEnd;
}

// Whether a report of `fault` on the injected fault's component can name it. On the rotor the two classes
// are two events: a shedding raised on a rotor whose ice stays is a false shedding, not the accretion's later
// name, and an accretion raised after a shedding is the accretion's (it is still there), not the shedding's.
bool can_name(const InjectedFault& i, const std::string& fault) {
  return i.component != "rotor" || fault == i.fault;
}

std::vector<InjectedFault> injected_of(const std::vector<ReportRow>& rows) {
  std::vector<InjectedFault> out;
  for (const auto& r : rows) out.push_back(r.injected);
  return out;
}

}  // namespace

std::pair<std::string, std::string> expected_detection(const std::string& target, const std::string& type) {
  auto ends = [&](const char* p) {
    return target.rfind(p, 0) == 0 ? target.substr(std::string(p).size()) : "";
  };
  if (type == "invalid") {
    if (!ends("blade_moment_").empty())
      return {"blade_moment_sensor_" + ends("blade_moment_"), "sensor_invalid"};
    if (target == "lidar" || target.rfind("lidar_v_", 0) == 0) return {"lidar", "sensor_invalid"};
  }
  if (!ends("blade_moment_").empty()) {
    const std::string c = "blade_moment_sensor_" + ends("blade_moment_");
    if (type == "drift") return {c, "sensor_drift"};
    if (type == "intermittent") return {c, "sensor_intermittent"};
    return {c, "sensor_abrupt"};
  }
  // A fixed value is sensor_stuck, a gain sensor_gain, an offset sensor_bias.
  const char* speed_or_pitch_class = type == "stuck"  ? "sensor_stuck"
                                     : type == "gain" ? "sensor_gain"
                                                      : "sensor_bias";
  if (target == "rotor_speed") return {"rotor_speed_sensor", speed_or_pitch_class};
  if (target == "generator_speed") return {"generator_speed_sensor", speed_or_pitch_class};
  if (!ends("pitch_").empty() && target.rfind("pitch_actuator_", 0) != 0)
    return {"pitch_sensor_" + ends("pitch_"), speed_or_pitch_class};
  if (target.rfind("pitch_actuator_", 0) == 0) return {target, type};
  if (target == "rotor") return {"rotor", type};
  if (target == "converter" && type == "torque_offset") return {"converter", "torque_offset"};
  if (target == "drive_train" && type == "efficiency") return {"drive_train", "efficiency_loss"};
  return {"", ""};  // anemometer, power and torque sensors, ...: no windfdi service covers them yet
}

double stop_ice_mass(const TurbineParams& turbine) {
  return kStopIceRise * turbine.lumped_inertia() * turbine.gear_ratio * turbine.gear_ratio /
         (turbine.ice_radius * turbine.ice_radius);
}

std::vector<InjectedFault> read_injected(const std::string& file) {
  const auto root = YamlSection::load_file(file);
  // The scenario's turbine as the plant finds it.
  const double stop_ice =
      stop_ice_mass(load_turbine_params_file(scenario_turbine_file(root, file, deploy_dir())));
  std::vector<InjectedFault> out;
  for (const auto& f : root.sequence("faults")) {
    InjectedFault i;
    i.turbine = f.require<std::string>("turbine");
    i.target = f.require<std::string>("target");
    i.type = f.require<std::string>("type");
    i.start = f.require_number("start", 0.0, 1e9);
    i.value = f.get_number("value", 0.0, -1e9, 1e9);
    i.ramp_in = f.get_number("ramp_in", 0.0, 0.0, 1e5);
    i.fraction = f.get_number("fraction", 1.0, 0.0, 1.0);
    // The plant's own reading of end, hold and the ramps (plant_sim/model/scenario.cpp).
    i.end = f.get_number("end", 1e300, i.start, 1e300);
    if (f.has("hold")) i.end = i.start + i.ramp_in + f.require_number("hold", 0.0, 1e5);
    if (i.end < 1e299) i.end += f.get_number("ramp_out", 0.0, 0.0, 1e5);
    std::tie(i.component, i.fault) = expected_detection(i.target, i.type);
    i.stop_ice_mass = stop_ice;
    out.push_back(i);
  }
  return out;
}

namespace {

// A raise that names another fault injected later on the same component, while that one is on, is that
// fault's report, not a name of the earlier one (a gauge's gain, then its signal lost while the gain lasted).
bool names_a_later_fault(const std::vector<InjectedFault>& injected, const InjectedFault& inj,
                         const std::string& fault, double td) {
  for (const auto& later : injected)
    if (&later != &inj && later.turbine == inj.turbine && later.component == inj.component &&
        later.start > inj.start && later.fault == fault && td >= later.start && td <= attribution_end(later))
      return true;
  return false;
}

}  // namespace

std::vector<ReportRow> match(const std::vector<InjectedFault>& injected,
                             const std::vector<HistoryRow>& history) {
  std::vector<ReportRow> rows;
  for (const auto& inj : injected) {
    ReportRow r;
    r.injected = inj;
    double received = 0.0;
    for (const auto& h : history) {
      if (h.kind != "fault" || h.turbine_id != inj.turbine) continue;
      const auto& d = h.data;
      if (d["component"] != inj.component || d["state"] != "raised") continue;
      const double td = detected_at(d);
      const std::string fault = d["fault"].get<std::string>();
      if (td < inj.start || td > attribution_end(inj) || !can_name(inj, fault)) continue;
      if (fault != inj.fault && names_a_later_fault(injected, inj, fault, td)) continue;
      if (r.detected) {
        const std::string& last = r.reclassified.empty() ? r.detected_fault : r.reclassified.back();
        if (fault != last) r.reclassified.push_back(fault);
        continue;
      }
      r.detected = true;
      r.detected_fault = fault;
      r.delay = td - inj.start;
      r.detected_while_active = td <= inj.end;
      received = h.received_at;
    }
    if (r.detected)
      for (const auto& h : history)
        if (h.kind == "config" && h.turbine_id == inj.turbine && h.received_at >= received) {
          const auto& d = h.data;
          r.reaction = "mode " + d["mode"].get<std::string>() + ", ipc " +
                       d["ipc_source"].get<std::string>() + ", ice " + d["ice_mode"].get<std::string>();
          break;
        }
    rows.push_back(r);
  }
  return rows;
}

std::vector<ExtraReport> extra_reports(const std::vector<InjectedFault>& injected,
                                       const std::vector<HistoryRow>& history) {
  // Every raised report with the time it stopped acting (its clear), per turbine.
  struct Raised {
    const nlohmann::json* data;
    double from, to;
  };
  std::map<std::string, std::vector<Raised>> by_turbine;
  std::map<std::string, std::size_t> open;  // turbine/source/component/fault -> index
  for (const auto& h : history) {
    if (h.kind != "fault") continue;
    const auto& d = h.data;
    const std::string key = h.turbine_id + "/" + d["source"].get<std::string>() + "/" +
                            d["component"].get<std::string>() + "/" + d["fault"].get<std::string>();
    auto& list = by_turbine[h.turbine_id];
    if (d["state"] == "raised") {
      if (open.count(key)) continue;  // a repeat (higher severity, transient-local replay)
      open[key] = list.size();
      list.push_back({&d, detected_at(d), 1e300});
    } else if (open.count(key)) {
      list[open[key]].to = d["t"].get<double>();
      open.erase(key);
    }
  }
  const isolation::IsolationConfig iso;
  std::vector<ExtraReport> out;
  for (const auto& [turbine, list] : by_turbine) {
    for (std::size_t r = 0; r < list.size(); ++r) {
      const auto& d = *list[r].data;
      const std::string component = d["component"].get<std::string>();
      const std::string fault = d["fault"].get<std::string>();
      const double td = list[r].from;
      bool injected_here = false;
      for (const auto& i : injected)
        injected_here |= i.turbine == turbine && i.component == component && td >= i.start &&
                         td <= attribution_end(i) && can_name(i, fault);
      if (injected_here) continue;
      // Isolation against the reports acting around its detection (as the arbiter saw them).
      std::vector<isolation::Report> reports = {
          {d["source"].get<std::string>(), component, d["fault"].get<std::string>(), td}};
      for (std::size_t s = 0; s < list.size(); ++s) {
        if (s == r || list[s].from > td + isolation::longest_lead(iso) || list[s].to < td - iso.common_window)
          continue;
        const auto& o = *list[s].data;
        reports.push_back({o["source"].get<std::string>(), o["component"].get<std::string>(),
                           o["fault"].get<std::string>(), list[s].from});
      }
      const auto v = isolation::isolate(reports, iso);
      out.push_back({turbine, component, d["fault"].get<std::string>(), d["source"].get<std::string>(), td,
                     v[0].secondary, v[0].explained_by});
    }
  }
  std::sort(out.begin(), out.end(),
            [](const ExtraReport& a, const ExtraReport& b) { return a.t_detected < b.t_detected; });
  return out;
}

double injected_ice(const std::vector<InjectedFault>& injected, const std::string& turbine, double t) {
  // The plant's accounting (plant_sim/model/turbine_sim.cpp): sheddings in time order, each of what is there.
  std::vector<const InjectedFault*> events;
  for (const auto& i : injected)
    if (i.turbine == turbine && (i.type == "ice_accretion" || i.type == "ice_shedding") && i.start <= t)
      events.push_back(&i);
  std::stable_sort(events.begin(), events.end(),
                   [](const InjectedFault* a, const InjectedFault* b) { return a->start < b->start; });
  double shed = 0.0;
  auto grown = [&](double at) {
    double ice = -shed;
    for (const auto* e : events)
      if (e->type == "ice_accretion" && e->start <= at)
        ice += e->value * (e->ramp_in > 0 ? std::min(1.0, (at - e->start) / e->ramp_in) : 1.0);
    return ice;
  };
  for (const auto* e : events)
    if (e->type == "ice_shedding") shed += e->fraction * std::max(0.0, grown(e->start));
  return std::max(0.0, grown(t));
}

std::vector<StopRecord> stops(const std::vector<InjectedFault>& injected,
                              const std::vector<HistoryRow>& history) {
  std::vector<StopRecord> out;
  std::map<std::string, bool> stopped;
  for (const auto& h : history) {
    if (h.kind != "config") continue;
    const bool stop = h.data["mode"] == "safe_stop";
    bool& was = stopped[h.turbine_id];
    if (stop && !was) {
      StopRecord s{h.turbine_id, h.data.value("t", 0.0), false};
      for (const auto& i : injected)
        s.warranted |= i.type == "hydraulic_leakage" && i.turbine == h.turbine_id && s.t >= i.start &&
                       s.t <= i.end + kStopAfterEnd;
      // Ice: at its stop level at any time in the last kStopIceWindow (the evidence a stop is decided on is
      // that old; a shedding seconds before the stop does not make it unwarranted).
      double stop_ice = 0.0;
      for (const auto& i : injected)
        if (i.turbine == h.turbine_id) stop_ice = i.stop_ice_mass;
      for (double back = 0.0; back <= kStopIceWindow && !s.warranted && stop_ice > 0.0; back += 1.0)
        s.warranted |= injected_ice(injected, h.turbine_id, s.t - back) >= kStopIceShare * stop_ice;
      out.push_back(s);
    }
    was = stop;
  }
  return out;
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
      found_later +=
          r.detected_fault != i.fault && !r.reclassified.empty() && r.reclassified.back() == i.fault;
    } else if (!i.component.empty()) {
      det = "MISSED";
    }
    std::snprintf(line, sizeof line, "%-6s %-36s %6.0fs  %-42s %-40s %-8s %s\n", i.turbine.c_str(),
                  (i.target + ":" + i.type).c_str(), i.start, exp.c_str(), det.c_str(), delay.c_str(),
                  r.reaction.empty() ? "-" : r.reaction.c_str());
    out << line;
  }
  const auto injected = injected_of(rows);
  int unexpected = 0, secondary = 0;
  for (const auto& x : extra_reports(injected, history)) {
    std::snprintf(line, sizeof line, "%s: %s %s %s from %s at %.1f s",
                  x.secondary ? "secondary" : "unexpected", x.turbine.c_str(), x.component.c_str(),
                  x.fault.c_str(), x.source.c_str(), x.t_detected);
    out << line << (x.secondary ? ", explained by " + x.explained_by + " (not acted on)" : "") << "\n";
    (x.secondary ? secondary : unexpected) += 1;
  }
  int unwarranted = 0;
  const auto stop_list = stops(injected, history);
  for (const auto& s : stop_list) {
    std::snprintf(line, sizeof line, "safe stop: %s at %.1f s, %s\n", s.turbine.c_str(), s.t,
                  s.warranted ? "warranted by an injected fault" : "NOT WARRANTED by any injected fault");
    out << line;
    unwarranted += !s.warranted;
  }
  out << found << " of " << expected << " covered faults detected with the right class first";
  if (found_later > 0) out << ", " << found_later << " more after a re-classification";
  out << "; " << unexpected << " unexpected fault report(s)";
  if (secondary > 0) out << ", " << secondary << " secondary (explained, not acted on)";
  out << "; " << stop_list.size() << " safe stop(s), " << unwarranted << " not warranted\n";
  return out.str();
}

namespace {
// True when the arbiter held the turbine in safe stop over the whole of [start, end]: a fault of the power
// path (converter, drive train) cannot show on a turbine that produces nothing.
bool stopped_throughout(const std::vector<HistoryRow>& history, const std::string& turbine, double start,
                        double end) {
  bool stopped = false;
  for (const auto& h : history) {
    if (h.kind != "config" || h.turbine_id != turbine || !h.data.contains("mode")) continue;
    const double t = h.data.value("t", h.received_at);
    const bool stop = h.data["mode"] == "safe_stop";
    if (t <= start) {
      stopped = stop;
    } else if (t <= end && !stop) {
      return false;
    }
  }
  return stopped;
}
}  // namespace

std::string render_benchmark_table(const std::vector<ReportRow>& rows,
                                   const std::vector<HistoryRow>& history) {
  std::ostringstream out;
  char line[512];
  out << "benchmark table (Odgaard, Stoustrup, Kinnaert: each fault detected and isolated while active)\n";
  std::snprintf(line, sizeof line, "%-6s %-36s %14s  %-9s %-9s %9s %9s\n", "TURB", "FAULT", "ACTIVE (s)",
                "DETECTED", "ISOLATED", "DELAY s", "SAMPLES");
  out << line;
  int covered = 0, ok = 0, unobservable = 0;
  for (const auto& r : rows) {
    const auto& i = r.injected;
    char active[48];
    if (i.end < 1e299)
      std::snprintf(active, sizeof active, "%.0f-%.0f", i.start, i.end);
    else
      std::snprintf(active, sizeof active, "%.0f-", i.start);
    if (i.component.empty()) {
      std::snprintf(line, sizeof line, "%-6s %-36s %14s  %-9s\n", i.turbine.c_str(),
                    (i.target + ":" + i.type).c_str(), active, "(not covered)");
      out << line;
      continue;
    }
    ++covered;
    const bool detected = r.detected && r.detected_while_active;
    const bool isolated = detected && r.detected_fault == i.fault;
    ok += isolated;
    char delay[32] = "-", samples[32] = "-";
    if (detected) {
      std::snprintf(delay, sizeof delay, "%.2f", r.delay);
      std::snprintf(samples, sizeof samples, "%.0f", r.delay / 0.01);  // the benchmark's 100 Hz samples
    }
    const bool stopped = !detected && stopped_throughout(history, i.turbine, i.start, std::min(i.end, 1e299));
    unobservable += stopped;
    std::snprintf(line, sizeof line, "%-6s %-36s %14s  %-9s %-9s %9s %9s\n", i.turbine.c_str(),
                  (i.target + ":" + i.type).c_str(), active, detected ? "yes" : (stopped ? "stopped" : "no"),
                  isolated ? "yes" : "no", delay, samples);
    out << line;
  }
  int false_alarms = 0;
  for (const auto& x : extra_reports(injected_of(rows), history)) false_alarms += !x.secondary;
  out << ok << " of " << covered << " covered faults detected and isolated while active; " << false_alarms
      << " false alarm(s)\n";
  if (unobservable > 0)
    out << unobservable
        << " fault(s) marked 'stopped' were active only while the arbiter held the turbine in a "
        << "safe stop: a stopped turbine shows no power-path fault\n";
  return out.str();
}

nlohmann::json report_json(const std::vector<ReportRow>& rows, const std::vector<HistoryRow>& history) {
  nlohmann::json out{{"faults", nlohmann::json::array()},
                     {"extra", nlohmann::json::array()},
                     {"stops", nlohmann::json::array()}};
  for (const auto& r : rows) {
    const auto& i = r.injected;
    out["faults"].push_back({{"turbine", i.turbine},
                             {"target", i.target},
                             {"type", i.type},
                             {"start", i.start},
                             {"ramp_in", i.ramp_in},
                             {"end", i.end < 1e299 ? nlohmann::json(i.end) : nlohmann::json(nullptr)},
                             {"component", i.component},
                             {"expected", i.fault},
                             {"detected", r.detected},
                             {"first", r.detected_fault},
                             {"then", r.reclassified},
                             {"delay", r.detected ? nlohmann::json(r.delay) : nlohmann::json(nullptr)},
                             {"while_active", r.detected_while_active}});
  }
  const auto injected = injected_of(rows);
  for (const auto& x : extra_reports(injected, history))
    out["extra"].push_back({{"turbine", x.turbine},
                            {"component", x.component},
                            {"fault", x.fault},
                            {"source", x.source},
                            {"t_detected", x.t_detected},
                            {"secondary", x.secondary},
                            {"explained_by", x.explained_by}});
  for (const auto& s : stops(injected, history))
    out["stops"].push_back({{"turbine", s.turbine}, {"t", s.t}, {"warranted", s.warranted}});
  return out;
}

std::vector<HistoryRow> read_history_jsonl(const std::string& file) {
  std::ifstream in(file);
  if (!in) throw ConfigError(file, 0, "", "cannot open the history file");
  std::vector<HistoryRow> rows;
  std::string text;
  for (int n = 1; std::getline(in, text); ++n) {
    if (text.find_first_not_of(" \t\r") == std::string::npos) continue;
    try {
      const auto j = nlohmann::json::parse(text);
      const auto& d = j.at("data");
      rows.push_back({j.at("received_at").get<double>(), j.at("kind").get<std::string>(),
                      d.value("turbine_id", std::string()), d});
    } catch (const std::exception& e) {
      throw ConfigError(file, n, "", std::string("not a history line: ") + e.what());
    }
  }
  return rows;
}

}  // namespace windfdi::farm
