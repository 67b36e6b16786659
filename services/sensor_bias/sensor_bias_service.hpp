// windfdi-sensor-bias's service spec (the shared diagnostic-service main runs it).
#pragma once

#include "bias_estimator.hpp"
#include "diagnostic_service.hpp"

namespace windfdi::sensor_bias {

ServiceSpec sensor_bias_spec();

}  // namespace windfdi::sensor_bias
