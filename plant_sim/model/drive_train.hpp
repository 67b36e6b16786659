// The turbine's dynamics: the two-mass drive train (Witczak et al. eqs 31-33), integrated by RK4; each
// blade's hydraulic pitch actuator is common's PitchActuator (pitch_actuator.hpp), which the services also
// use.
#pragma once

#include "pitch_actuator.hpp"
#include "turbine_params.hpp"

namespace windfdi::plant {

/// Rotor speed, generator speed (rad/s) and shaft torsion (rad).
struct DriveTrain {
  double rotor_speed = 0.0;
  double generator_speed = 0.0;
  double torsion = 0.0;

  /// One RK4 step of h (s): aerodynamic torque on the rotor, generator torque (N m), the rotor's inertia now
  /// (iced, kg m^2) and the drive-train efficiency (a fault changes it). Speeds stay non-negative.
  void step(const TurbineParams& p, double rotor_inertia, double efficiency, double aero_torque,
            double generator_torque, double h);
};

}  // namespace windfdi::plant
