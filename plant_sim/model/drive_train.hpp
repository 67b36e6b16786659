// The turbine's dynamics: the two-mass drive train (Witczak et al. eqs 31-33) and one blade's hydraulic pitch
// actuator (Witczak et al. eq 34 with the -omega_n^2 beta term it lacks; Wu & Li eqs 11-13 for its faults),
// each integrated by RK4.
#pragma once

#include "turbine_params.hpp"

namespace windfdi::plant {

/// beta'' = -2 zeta omega_n beta' - omega_n^2 (beta - beta_ref), rate and angle limited.
struct PitchActuator {
  double angle = 0.0;  ///< deg
  double rate = 0.0;   ///< deg/s
  void step(double reference, double h, double omega_n, double zeta, double rate_limit, double min_angle,
            double max_angle);
};

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
