// Canonical names of the arbiter's control settings.
#include "control_modes.hpp"

namespace windfdi::control {

const char* to_string(OperatingMode m) {
  switch (m) {
    case OperatingMode::kNormal:
      return "normal";
    case OperatingMode::kDegraded:
      return "degraded";
    case OperatingMode::kSafeStop:
      return "safe_stop";
  }
  return "?";
}

const char* to_string(IpcSource s) {
  switch (s) {
    case IpcSource::kStrainGauge:
      return "strain_gauge";
    case IpcSource::kLidarModel:
      return "lidar_model";
    case IpcSource::kOff:
      return "off";
  }
  return "?";
}

const char* to_string(IceMode m) {
  switch (m) {
    case IceMode::kNormal:
      return "normal";
    case IceMode::kAdapted:
      return "adapted";
    case IceMode::kStop:
      return "stop";
  }
  return "?";
}

}  // namespace windfdi::control
