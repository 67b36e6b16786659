// windfdi-blade-load: blade-root moment sensor faults from the first harmonic, strain gauge vs LIDAR model
// (Stotsky 2014).
#include "blade_load_service.hpp"

int main(int argc, char** argv) {
  return windfdi::run_diagnostic_service(argc, argv, windfdi::blade_load::blade_load_spec());
}
