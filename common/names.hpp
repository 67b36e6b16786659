// Canonical component and fault-class names (docs/architecture.md "Canonical names"), shared by every module.
#pragma once

#include <string>
#include <vector>

namespace windfdi {

/// Fault classes in the order of the IDL enum FaultClass (index = enum value).
const std::vector<std::string>& fault_class_names();
/// Severities in the order of the IDL enum Severity.
const std::vector<std::string>& severity_names();
/// Every canonical diagnosable component (service names, used for health, are not listed).
const std::vector<std::string>& component_names();
/// Names of the diagnostic services, which are also components for `service_lost`.
const std::vector<std::string>& service_names();

/// What may speak on wt/health: the diagnostic services, "plant", "arbiter" and "farm_monitor". Health from
/// any other name is foreign (a peer on an unsecured domain) and is dropped.
bool is_health_source(const std::string& name);

/// Index of `name` in `names`, or -1.
int name_index(const std::vector<std::string>& names, const std::string& name);
bool is_component(const std::string& name);
/// The fault classes that make sense on a component (e.g. pitch actuator classes on pitch_actuator_2).
std::vector<std::string> fault_classes_for(const std::string& component);
/// Blade index 0..2 of a per-blade component ("pitch_actuator_2" -> 1, "blade_moment_sensor_3" -> 2), or -1.
int blade_index(const std::string& component);

}  // namespace windfdi
