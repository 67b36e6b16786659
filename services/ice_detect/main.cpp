// windfdi-ice-detect: ice accretion and shedding from the estimated rotor inertia (Stotsky & Egardt 2013).
#include "ice_service.hpp"

int main(int argc, char** argv) {
  return windfdi::run_diagnostic_service(argc, argv, windfdi::ice_detect::ice_detect_spec());
}
