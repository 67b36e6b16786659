// Conversions between the IDL topic types and the plain structs the cores use.
#include "convert.hpp"

#include <algorithm>
#include <stdexcept>

#include "names.hpp"

namespace windfdi::bus {

FrameSample to_sample(const windfdi::TurbineSample& s) {
  FrameSample f;
  f.sequence = s.sequence();
  f.t = s.t();
  f.rotor_speed = s.rotor_speed();
  f.generator_speed = s.generator_speed();
  f.gen_torque = s.gen_torque();
  f.gen_torque_ref = s.gen_torque_ref();
  f.power = s.power();
  f.wind_hub = s.wind_hub();
  f.azimuth = s.azimuth();
  f.pitch = s.pitch();
  f.pitch_ref = s.pitch_ref();
  f.blade_moment = s.blade_moment();
  f.valid_mask = s.valid_mask();
  return f;
}

windfdi::TurbineSample to_idl(const FrameSample& f) {
  windfdi::TurbineSample s;
  s.sequence(f.sequence);
  s.t(f.t);
  s.rotor_speed(f.rotor_speed);
  s.generator_speed(f.generator_speed);
  s.gen_torque(f.gen_torque);
  s.gen_torque_ref(f.gen_torque_ref);
  s.power(f.power);
  s.wind_hub(f.wind_hub);
  s.azimuth(f.azimuth);
  s.pitch(f.pitch);
  s.pitch_ref(f.pitch_ref);
  s.blade_moment(f.blade_moment);
  s.valid_mask(f.valid_mask);
  return s;
}

std::string fault_class_name(windfdi::FaultClass c) {
  const auto& n = fault_class_names();
  return static_cast<std::size_t>(c) < n.size() ? n[c] : "unknown";
}

std::string severity_name(windfdi::Severity s) {
  const auto& n = severity_names();
  return static_cast<std::size_t>(s) < n.size() ? n[s] : "unknown";
}

bool fault_class_from_name(const std::string& name, windfdi::FaultClass& out) {
  const int i = name_index(fault_class_names(), name);
  if (i < 0) return false;
  out = static_cast<windfdi::FaultClass>(i);
  return true;
}

windfdi::FaultReport to_idl(const FaultEvent& e) {
  windfdi::FaultReport r;
  windfdi::FaultClass fc;
  if (!fault_class_from_name(e.fault, fc))
    throw std::invalid_argument("unknown fault class '" + e.fault + "'");
  const int sev = name_index(severity_names(), e.severity);
  if (sev < 0) throw std::invalid_argument("unknown severity '" + e.severity + "'");
  r.t(e.t);
  r.turbine_id(e.turbine_id);
  r.source(e.source);
  r.component(e.component);
  r.state(e.raised ? windfdi::FAULT_STATE_RAISED : windfdi::FAULT_STATE_CLEARED);
  r.fault_class(fc);
  r.severity(static_cast<windfdi::Severity>(sev));
  r.t_detected(e.t_detected);
  r.statistic(e.statistic);
  r.threshold(e.threshold);
  r.size(e.size);
  r.detail(e.detail);
  return r;
}

FaultEvent to_event(const windfdi::FaultReport& r) {
  FaultEvent e;
  e.t = r.t();
  e.turbine_id = r.turbine_id();
  e.source = r.source();
  e.component = r.component();
  e.fault = fault_class_name(r.fault_class());
  e.raised = r.state() == windfdi::FAULT_STATE_RAISED;
  e.severity = severity_name(r.severity());
  e.t_detected = r.t_detected();
  e.statistic = r.statistic();
  e.threshold = r.threshold();
  e.size = r.size();
  e.detail = r.detail().substr(0, kMaxReportDetail);
  return e;
}

static_assert(static_cast<int>(windfdi::MODE_NORMAL) == static_cast<int>(control::OperatingMode::kNormal) &&
              static_cast<int>(windfdi::MODE_DEGRADED) ==
                  static_cast<int>(control::OperatingMode::kDegraded) &&
              static_cast<int>(windfdi::MODE_SAFE_STOP) ==
                  static_cast<int>(control::OperatingMode::kSafeStop));
static_assert(static_cast<int>(windfdi::IPC_STRAIN_GAUGE) ==
                  static_cast<int>(control::IpcSource::kStrainGauge) &&
              static_cast<int>(windfdi::IPC_LIDAR_MODEL) ==
                  static_cast<int>(control::IpcSource::kLidarModel) &&
              static_cast<int>(windfdi::IPC_OFF) == static_cast<int>(control::IpcSource::kOff));
static_assert(static_cast<int>(windfdi::ICE_NORMAL) == static_cast<int>(control::IceMode::kNormal) &&
              static_cast<int>(windfdi::ICE_ADAPTED) == static_cast<int>(control::IceMode::kAdapted) &&
              static_cast<int>(windfdi::ICE_STOP) == static_cast<int>(control::IceMode::kStop));

namespace {
// The enums are ordered by how conservative they are: a value beyond the last (a newer peer) reads as the
// last.
template <class To, class From>
To clamped(From v, To last) {
  return static_cast<To>(std::clamp(static_cast<int>(v), 0, static_cast<int>(last)));
}
}  // namespace

windfdi::OperatingMode to_idl(control::OperatingMode m) { return static_cast<windfdi::OperatingMode>(m); }
windfdi::IpcSource to_idl(control::IpcSource s) { return static_cast<windfdi::IpcSource>(s); }
windfdi::IceMode to_idl(control::IceMode m) { return static_cast<windfdi::IceMode>(m); }
control::OperatingMode from_idl(windfdi::OperatingMode m) {
  return clamped(m, control::OperatingMode::kSafeStop);
}
control::IpcSource from_idl(windfdi::IpcSource s) { return clamped(s, control::IpcSource::kOff); }
control::IceMode from_idl(windfdi::IceMode m) { return clamped(m, control::IceMode::kStop); }

}  // namespace windfdi::bus
