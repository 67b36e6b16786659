// Canonical component and fault-class names.
#include "names.hpp"

#include <algorithm>

#include "windfdi_services.hpp"

namespace windfdi {

const std::vector<std::string>& fault_class_names() {
  static const std::vector<std::string> n = {
      "none",          "sensor_abrupt",   "sensor_drift",      "sensor_intermittent",
      "sensor_bias",   "pump_wear",       "hydraulic_leakage", "high_air_content",
      "ice_accretion", "ice_shedding",    "sensor_invalid",    "service_lost",
      "torque_offset", "efficiency_loss", "sensor_stuck",      "sensor_gain"};
  return n;
}

const std::vector<std::string>& severity_names() {
  static const std::vector<std::string> n = {"info", "warning", "fault", "critical"};
  return n;
}

const std::vector<std::string>& component_names() {
  static const std::vector<std::string> n = {"blade_moment_sensor_1",
                                             "blade_moment_sensor_2",
                                             "blade_moment_sensor_3",
                                             "rotor_speed_sensor",
                                             "generator_speed_sensor",
                                             "pitch_sensor_1",
                                             "pitch_sensor_2",
                                             "pitch_sensor_3",
                                             "pitch_actuator_1",
                                             "pitch_actuator_2",
                                             "pitch_actuator_3",
                                             "rotor",
                                             "lidar",
                                             "converter",
                                             "drive_train"};
  return n;
}

const std::vector<std::string>& service_names() {
  static const std::vector<std::string> n = {WINDFDI_DIAGNOSTIC_SERVICE_NAMES};  // services/services.list
  return n;
}

bool is_health_source(const std::string& name) {
  return name == "plant" || name == "arbiter" || name == "farm_monitor" ||
         name_index(service_names(), name) >= 0;
}

int name_index(const std::vector<std::string>& names, const std::string& name) {
  const auto it = std::find(names.begin(), names.end(), name);
  return it == names.end() ? -1 : static_cast<int>(it - names.begin());
}

bool is_component(const std::string& name) {
  return name_index(component_names(), name) >= 0 || name_index(service_names(), name) >= 0;
}

std::vector<std::string> fault_classes_for(const std::string& c) {
  auto starts = [&](const char* p) { return c.rfind(p, 0) == 0; };
  if (starts("blade_moment_sensor_"))
    return {"sensor_abrupt", "sensor_drift", "sensor_intermittent", "sensor_invalid"};
  if (c == "rotor_speed_sensor" || c == "generator_speed_sensor" || starts("pitch_sensor_"))
    return {"sensor_bias", "sensor_stuck", "sensor_gain", "sensor_invalid"};
  if (starts("pitch_actuator_")) return {"pump_wear", "hydraulic_leakage", "high_air_content"};
  if (c == "rotor") return {"ice_accretion", "ice_shedding"};
  if (c == "lidar") return {"sensor_invalid"};
  if (c == "converter") return {"torque_offset"};
  if (c == "drive_train") return {"efficiency_loss"};
  if (name_index(service_names(), c) >= 0) return {"service_lost"};
  return {};
}

int blade_index(const std::string& component) {
  const std::size_t n = component.size();
  if (n < 3 || component[n - 2] != '_') return -1;
  const char last = component[n - 1];
  return last >= '1' && last <= '3' ? last - '1' : -1;
}

}  // namespace windfdi
