// windfdi-ice-detect's service spec (the shared diagnostic-service main runs it).
#pragma once

#include "diagnostic_service.hpp"
#include "ice_turbine.hpp"

namespace windfdi::ice_detect {

ServiceSpec ice_detect_spec();

}  // namespace windfdi::ice_detect
