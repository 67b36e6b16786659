// When a scenario fault acts (the schedule of deploy/scenarios/README.md).
#include "fault_schedule.hpp"

#include <algorithm>

namespace windfdi::plant {

double pitch_fault_indicator(const FaultSpec& f, double t) {
  if (t < f.start) return 0.0;
  if (t < f.start + f.ramp_in) return f.alpha * (t - f.start) / f.ramp_in;
  if (t < f.end) return f.alpha;
  if (f.ramp_out > 0.0 && t < f.end + f.ramp_out) return f.alpha * (1.0 - (t - f.end) / f.ramp_out);
  return 0.0;
}

bool fault_active(const FaultSpec& f, double t) {
  if (f.target.rfind("pitch_actuator_", 0) == 0) return pitch_fault_indicator(f, t) > 0.0;
  if (f.type == "ice_shedding") return t >= f.start && t < std::min(f.end, f.start + 60.0);
  return t >= f.start && t < f.end;
}

}  // namespace windfdi::plant
