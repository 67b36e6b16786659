// windfdi-pitch-diag: pitch-actuator fault diagnosis by model identification (Wu & Li).
#include "pitch_service.hpp"

int main(int argc, char** argv) {
  return windfdi::run_diagnostic_service(argc, argv, windfdi::pitch_diag::pitch_diag_spec());
}
