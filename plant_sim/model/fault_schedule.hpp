// When a scenario fault acts, and how far a gradual pitch-actuator fault has gone (Wu & Li eqs 11-13).
#pragma once

#include "scenario.hpp"

namespace windfdi::plant {

/// Wu & Li's fault indicator at time t (s): 0 before the start, ramped in to `alpha`, held until `end`,
/// ramped out (abrupt when the ramps are 0).
double pitch_fault_indicator(const FaultSpec& f, double t);

/// Whether the fault acts at time t: a pitch-actuator fault while its indicator is positive, an ice shedding
/// for the minute after it starts, any other from its start to its end.
bool fault_active(const FaultSpec& f, double t);

}  // namespace windfdi::plant
