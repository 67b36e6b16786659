// Conversions between the IDL topic types and the plain structs the cores use.
#pragma once

#include <string>

#include "ControlConfiguration.h"
#include "FaultReport.h"
#include "TurbineFrame.h"
#include "control_modes.hpp"
#include "fault_event.hpp"
#include "frame_sample.hpp"

namespace windfdi::bus {

FrameSample to_sample(const windfdi::TurbineSample& s);
windfdi::TurbineSample to_idl(const FrameSample& s);

/// Throws std::invalid_argument for a class or severity name that is not canonical.
windfdi::FaultReport to_idl(const FaultEvent& e);
FaultEvent to_event(const windfdi::FaultReport& r);

/// The control settings on the wire and back; a value beyond the enum (a newer peer) reads as the most
/// conservative setting.
windfdi::OperatingMode to_idl(control::OperatingMode m);
windfdi::IpcSource to_idl(control::IpcSource s);
windfdi::IceMode to_idl(control::IceMode m);
control::OperatingMode from_idl(windfdi::OperatingMode m);
control::IpcSource from_idl(windfdi::IpcSource s);
control::IceMode from_idl(windfdi::IceMode m);

std::string fault_class_name(windfdi::FaultClass c);
std::string severity_name(windfdi::Severity s);
/// False when `name` is not a canonical fault class.
bool fault_class_from_name(const std::string& name, windfdi::FaultClass& out);

}  // namespace windfdi::bus
