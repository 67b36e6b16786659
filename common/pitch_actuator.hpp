// A blade's hydraulic pitch actuator: the plant's dynamics and the services' nominal response to a reference
// (Witczak et al. eq 34 with the -omega_n^2 beta term it lacks; Wu & Li eqs 11-13 for its faults).
#pragma once

namespace windfdi {

/// beta'' = -2 zeta omega_n beta' - omega_n^2 (beta - beta_ref), rate and angle limited, integrated by RK4.
struct PitchActuator {
  double angle = 0.0;  ///< deg
  double rate = 0.0;   ///< deg/s
  void step(double reference, double h, double omega_n, double zeta, double rate_limit, double min_angle,
            double max_angle);
};

}  // namespace windfdi
