// windfdi-ice-detect's service spec (the shared diagnostic-service main runs it).
#pragma once

#include "aero_power_input.hpp"
#include "diagnostic_service.hpp"
#include "ice_detector.hpp"

namespace windfdi::ice_detect {

ServiceSpec ice_detect_spec();

}  // namespace windfdi::ice_detect
