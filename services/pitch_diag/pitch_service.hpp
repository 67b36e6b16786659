// windfdi-pitch-diag's service spec (the shared diagnostic-service main runs it).
#pragma once

#include "diagnostic_service.hpp"
#include "pitch_diagnoser.hpp"

namespace windfdi::pitch_diag {

ServiceSpec pitch_diag_spec();

}  // namespace windfdi::pitch_diag
