// The vertical wind profile through two LIDAR beams: a power law v(z) = v_hub (z / H)^alpha (Stotsky 2014,
// Figure 1), read by the plant's LIDAR-model IPC and by blade_load's LIDAR load model.
#pragma once

#include <cmath>

namespace windfdi {

struct ShearProfile {
  double hub_height = 0.0;  ///< m, H
  double exponent = 0.0;    ///< alpha (-)
  double hub_speed = 0.0;   ///< m/s at hub height

  /// Wind speed at `height` (m above ground).
  double at(double height) const { return hub_speed * std::pow(height / hub_height, exponent); }
};

/// The profile through the upper and lower beams, which sample hub height +/- `beam_offset` (m). Both speeds
/// must be positive.
inline ShearProfile shear_from_beams(double v_upper, double v_lower, double hub_height, double beam_offset) {
  const double h = hub_height, r = beam_offset;
  ShearProfile p;
  p.hub_height = h;
  p.exponent = std::log(v_upper / v_lower) / std::log((h + r) / (h - r));
  p.hub_speed = v_upper / std::pow((h + r) / h, p.exponent);
  return p;
}

}  // namespace windfdi
