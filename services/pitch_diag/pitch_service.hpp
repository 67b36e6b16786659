// windfdi-pitch-diag's service spec (the shared diagnostic-service main runs it).
#pragma once

#include "diagnostic_service.hpp"
#include "pitch_diagnoser.hpp"

namespace windfdi::pitch_diag {

/// A PitchEvent in the canonical FaultEvent form (turbine and source are filled in by the service main).
FaultEvent to_fault_event(const PitchEvent& e);

ServiceSpec pitch_diag_spec();

}  // namespace windfdi::pitch_diag
