// Sensor noise and sensor faults.
#include "sensors.hpp"

#include <cmath>

#include "fault_schedule.hpp"

namespace windfdi::plant {

Sensors::Sensors(const std::vector<FaultSpec>& faults, double dt)
    : faults_(faults), dt_(dt), stuck_value_(faults.size(), 0.0), stuck_latched_(faults.size(), false) {}

double Sensors::measure(const std::string& channel, double true_value, double noise_std, double t,
                        bool inject, RandomSource& random) {
  double v = true_value + noise_std * random.normal();
  if (!inject) return v;
  for (std::size_t i = 0; i < faults_.size(); ++i) {
    const FaultSpec& f = faults_[i];
    const bool targets = f.target == channel || (f.target == "lidar" && channel.rfind("lidar_v_", 0) == 0);
    if (!targets) continue;
    if (!fault_active(f, t)) {
      stuck_latched_[i] = false;
      continue;
    }
    const double since = t - f.start;
    if (f.type == "bias" || f.type == "offset") {
      v += f.value;
    } else if (f.type == "bias_paper") {
      // Witczak et al. eqs 41-42: a state-dependent bias, k counted from the fault's start.
      const double k = std::floor(since / dt_ + 1e-6);
      v += f.amplitude * (true_value * std::sin(k / 500.0) + true_value * std::sin(k / 1000.0) + true_value);
    } else if (f.type == "gain") {
      v *= f.gain;
    } else if (f.type == "drift") {
      v += f.rate * since;
    } else if (f.type == "stuck") {
      if (!stuck_latched_[i]) {
        stuck_value_[i] = f.has_value ? f.value : v;
        stuck_latched_[i] = true;
      }
      v = stuck_value_[i];
    } else if (f.type == "intermittent") {
      if (std::fmod(since, f.period) < f.duty * f.period) v = f.gain * v + f.value;
    } else if (f.type == "invalid") {
      v = kNaN;
    }
  }
  return v;
}

}  // namespace windfdi::plant
