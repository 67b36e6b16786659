// windfdi-drive-train's service spec (the shared diagnostic-service main runs it).
#pragma once

#include "diagnostic_service.hpp"
#include "drive_train_diagnoser.hpp"

namespace windfdi::drive_train {

ServiceSpec drive_train_spec();

}  // namespace windfdi::drive_train
