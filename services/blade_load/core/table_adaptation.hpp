// Adaptation of the load table k_M(lambda, pitch) in uniform wind (Stotsky 2014, last section): over a
// segment of healthy uniform-wind revolutions at one operating point, the model's mean load is pulled toward
// the gauges'.
#pragma once

#include <array>

#include "load_model.hpp"

namespace windfdi::blade_load {

/// Load-table adaptation in uniform wind (YAML keys `adapt`, `uniform_shear` and `adapt_` + the field name;
/// the two spreads have none).
struct AdaptationConfig {
  bool enabled = true;             ///< false: the shipped table is kept as it is
  double uniform_shear = 0.04;     ///< |LIDAR shear exponent| below which the wind is uniform
  int revolutions = 20;            ///< consecutive uniform revolutions averaged for one update
  double gain = 0.2;               ///< share of the way to the measured ratio per update (0..1)
  double bound = 0.15;             ///< largest correction of the shipped table, +/- share
  double sigma_lambda = 0.5;       ///< tip-speed-ratio width of an update on the surface
  double sigma_pitch = 1.5;        ///< deg, pitch width of an update
  double max_lambda_spread = 0.5;  ///< operating point must stay within this lambda range while averaging
  double max_pitch_spread = 2.0;   ///< and within this pitch range (deg)
};

class TableAdaptation {
 public:
  explicit TableAdaptation(const AdaptationConfig& c) : c_(c) {}
  /// One sample of the LIDAR model's operating point: shear exponent, tip-speed ratio, mean pitch (deg).
  void add_sample(double shear, double lambda, double pitch);
  /// The windows restart: the operating point since the last revolution is dropped.
  void restart();
  /// Once per revolution, with each blade's window mean load from its gauge and from the model (N m).
  /// `healthy`: every blade and the LIDAR were usable and nothing is raised, exceeding or held (else the
  /// segment ends). Adapts `table` when a segment of `revolutions` uniform-wind revolutions is complete.
  void revolution(bool healthy, const std::array<double, 3>& mean_sensor,
                  const std::array<double, 3>& mean_model, LoadTable& table);
  /// Table updates so far.
  int adaptations() const { return adaptations_; }

 private:
  AdaptationConfig c_;
  // The operating point's sums since the last revolution.
  double shear_sum_ = 0.0, lambda_sum_ = 0.0, pitch_sum_ = 0.0;
  int op_n_ = 0;
  // The segment: revolutions, mean loads and the operating point's range and sums.
  int n_ = 0;
  double sensor_ = 0, model_ = 0, lmin_ = 0, lmax_ = 0, pmin_ = 0, pmax_ = 0, lsum_ = 0, psum_ = 0;
  int adaptations_ = 0;
};

}  // namespace windfdi::blade_load
