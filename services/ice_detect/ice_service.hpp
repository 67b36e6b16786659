// windfdi-ice-detect's service spec (the shared diagnostic-service main runs it).
#pragma once

#include "diagnostic_service.hpp"
#include "ice_detector.hpp"

namespace windfdi::ice_detect {

/// Aerodynamic power of a sample: the recording's `aero_power` when present, else the turbine model on
/// measured wind, rotor speed and each blade's pitch; NaN when an input is missing or out of range.
double aero_power_of(const FrameSample& s, const AeroModel& aero);

ServiceSpec ice_detect_spec();

}  // namespace windfdi::ice_detect
