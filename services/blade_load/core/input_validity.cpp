// Usable inputs of each sample and sensor_invalid on blade-moment gauges and the LIDAR.
#include "input_validity.hpp"

#include <cmath>
#include <string>

namespace windfdi::blade_load {

namespace {
FaultEvent invalid_event(double t, const std::string& component, bool raised, double since) {
  FaultEvent e;
  e.t = t;
  e.t_detected = since;
  e.component = component;
  e.fault = "sensor_invalid";
  e.raised = raised;
  e.severity = "fault";
  return e;
}
}  // namespace

std::array<bool, 3> InputValidity::moments(const FrameSample& s, std::vector<FaultEvent>& events,
                                           std::array<bool, 3>& lost) {
  // NaN or out of range is a rejected channel; for too long, sensor_invalid.
  const double t = s.t;
  std::array<bool, 3> ok{};
  for (int b = 0; b < 3; ++b) {
    const double m = s.blade_moment[b];
    // Named only for an event: a string built per sample and blade was a heap allocation on the hot path.
    const auto component = [b] { return "blade_moment_sensor_" + std::to_string(b + 1); };
    ok[b] = std::isfinite(m) && std::fabs(m) <= c_.max_moment && (s.valid_mask & (kValidBladeMoment1 << b));
    lost[b] = false;
    if (ok[b]) {
      if (invalid_raised_[b]) {
        events.push_back(invalid_event(t, component(), false, invalid_since_[b]));
        invalid_raised_[b] = false;
      }
      invalid_since_[b] = -1.0;
    } else {
      if (invalid_since_[b] < 0) invalid_since_[b] = t;
      if (!invalid_raised_[b] && t - invalid_since_[b] >= c_.invalid_time) {
        FaultEvent e = invalid_event(t, component(), true, invalid_since_[b]);
        e.statistic = t - invalid_since_[b];
        e.threshold = c_.invalid_time;
        e.detail = "blade moment missing, NaN or beyond " + std::to_string(c_.max_moment) + " N m";
        events.push_back(e);
        invalid_raised_[b] = true;
        lost[b] = true;
      }
    }
  }
  return ok;
}

std::array<double, 3> InputValidity::pitch(const FrameSample& s) {
  std::array<double, 3> pitch = s.pitch;
  double sum = 0.0;
  int n = 0;
  for (int b = 0; b < 3; ++b)
    if (std::isfinite(pitch[b]) && (s.valid_mask & (kValidPitch1 << b))) sum += pitch[b], ++n;
  const double fill = n > 0 ? sum / n : last_pitch_mean_;
  last_pitch_mean_ = fill;
  for (int b = 0; b < 3; ++b)
    if (!std::isfinite(pitch[b]) || !(s.valid_mask & (kValidPitch1 << b))) pitch[b] = fill;
  return pitch;
}

bool InputValidity::lidar(double t, bool model_ok, std::vector<FaultEvent>& events) {
  if (model_ok) {
    if (lidar_raised_) {
      events.push_back(invalid_event(t, "lidar", false, lidar_bad_since_));
      lidar_raised_ = false;
    }
    lidar_bad_since_ = -1.0;
    lidar_ok_ = true;
    return false;
  }
  if (t < lidar_grace_until_) return false;
  if (lidar_bad_since_ < 0) lidar_bad_since_ = t;
  if (!(t - lidar_bad_since_ >= c_.invalid_time && lidar_ok_)) return false;
  // Fall back to sensor-only (cross-blade) monitoring until the LIDAR is back.
  lidar_ok_ = false;
  if (!lidar_raised_) {
    FaultEvent e = invalid_event(t, "lidar", true, lidar_bad_since_);
    e.statistic = t - lidar_bad_since_;
    e.threshold = c_.invalid_time;
    e.severity = "warning";
    e.detail = "no delayed LIDAR speeds: sensor-only (cross-blade) monitoring";
    events.push_back(e);
    lidar_raised_ = true;
  }
  return true;
}

}  // namespace windfdi::blade_load
