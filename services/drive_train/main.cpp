// windfdi-drive-train: converter torque offset and drive-train efficiency loss (the FDI/FTC benchmark's
// faults 8 and 9).
#include "drive_train_service.hpp"

int main(int argc, char** argv) {
  return windfdi::run_diagnostic_service(argc, argv, windfdi::drive_train::drive_train_spec());
}
