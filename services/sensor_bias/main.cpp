// windfdi-sensor-bias: speed and pitch sensor-bias estimation with a quadratic-boundedness observer (Witczak
// et al.).
#include "sensor_bias_service.hpp"

int main(int argc, char** argv) {
  return windfdi::run_diagnostic_service(argc, argv, windfdi::sensor_bias::sensor_bias_spec());
}
