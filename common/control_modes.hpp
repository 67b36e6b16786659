// The arbiter's control settings (operating mode, IPC source, ice mode): one definition for the plant, the
// arbiter and the farm monitor, with their canonical names. The IDL enums (idl/Types.idl) carry the same
// values on the wire; common/dds/convert.hpp converts, checked at compile time.
#pragma once

#include <string>

namespace windfdi::control {

enum class OperatingMode { kNormal = 0, kDegraded = 1, kSafeStop = 2 };
/// Where individual pitch control takes its blade loads from.
enum class IpcSource { kStrainGauge = 0, kLidarModel = 1, kOff = 2 };
enum class IceMode { kNormal = 0, kAdapted = 1, kStop = 2 };

/// "normal", "degraded", "safe_stop"
const char* to_string(OperatingMode m);
/// "strain_gauge", "lidar_model", "off"
const char* to_string(IpcSource s);
/// "normal", "adapted", "stop"
const char* to_string(IceMode m);

}  // namespace windfdi::control
