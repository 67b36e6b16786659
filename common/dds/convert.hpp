// Conversions between the IDL topic types and the plain structs the cores use.
#pragma once

#include <string>

#include "FaultReport.h"
#include "TurbineFrame.h"
#include "fault_event.hpp"
#include "frame_sample.hpp"

namespace windfdi::bus {

FrameSample to_sample(const windfdi::TurbineSample& s);
windfdi::TurbineSample to_idl(const FrameSample& s);

/// Throws std::invalid_argument for a class or severity name that is not canonical.
windfdi::FaultReport to_idl(const FaultEvent& e);
FaultEvent to_event(const windfdi::FaultReport& r);

std::string fault_class_name(windfdi::FaultClass c);
std::string severity_name(windfdi::Severity s);
/// False when `name` is not a canonical fault class.
bool fault_class_from_name(const std::string& name, windfdi::FaultClass& out);

}  // namespace windfdi::bus
