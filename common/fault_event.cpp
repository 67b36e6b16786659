// A fault event and its JSON Lines form.
#include "fault_event.hpp"

#include <algorithm>
#include <cmath>

#include "names.hpp"

namespace windfdi {

namespace {
// JSON has no NaN: a statistic that is not a number is written as null.
nlohmann::json number_or_null(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); }
double number_from(const nlohmann::json& j, const char* key) {
  return j.contains(key) && j[key].is_number() ? j[key].get<double>() : std::nan("");
}
}  // namespace

nlohmann::json to_json(const FaultEvent& e) {
  return nlohmann::json{{"t", e.t},
                        {"turbine_id", e.turbine_id},
                        {"source", e.source},
                        {"component", e.component},
                        {"fault", e.fault},
                        {"state", e.raised ? "raised" : "cleared"},
                        {"severity", e.severity},
                        {"statistic", number_or_null(e.statistic)},
                        {"threshold", number_or_null(e.threshold)},
                        {"size", number_or_null(e.size)},
                        {"t_detected", e.t_detected},
                        {"detail", e.detail}};
}

FaultEvent fault_event_from_json(const nlohmann::json& j) {
  FaultEvent e;
  e.t = j.at("t").get<double>();
  e.turbine_id = j.at("turbine_id").get<std::string>();
  e.source = j.at("source").get<std::string>();
  e.component = j.at("component").get<std::string>();
  e.fault = j.at("fault").get<std::string>();
  e.raised = j.at("state").get<std::string>() == "raised";
  e.severity = j.value("severity", std::string("fault"));
  e.statistic = number_from(j, "statistic");
  e.threshold = number_from(j, "threshold");
  e.size = number_from(j, "size");
  e.t_detected = j.value("t_detected", e.t);
  e.detail = j.value("detail", std::string());
  return e;
}

std::string foreign_report_reason(const FaultEvent& e) {
  if (name_index(service_names(), e.source) < 0) return "its source is no diagnostic service";
  if (!is_component(e.component)) return "its component is not a canonical one";
  const auto classes = fault_classes_for(e.component);
  if (std::find(classes.begin(), classes.end(), e.fault) == classes.end())
    return "its class is not one of " + e.component.substr(0, 64);
  if (name_index(severity_names(), e.severity) < 0) return "its severity is unknown";
  return "";
}

}  // namespace windfdi
