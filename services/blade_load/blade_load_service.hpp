// windfdi-blade-load's service spec (the shared diagnostic-service main runs it).
#pragma once

#include "blade_load_monitor.hpp"
#include "diagnostic_service.hpp"

namespace windfdi::blade_load {

/// Replaces every `{turbine}` in a path by the turbine id (one state file per turbine).
std::string state_path_for(const std::string& pattern, const std::string& turbine_id);

ServiceSpec blade_load_spec();

}  // namespace windfdi::blade_load
