// The wind one turbine sees: turbulence and shear at the LIDAR's measurement plane, carried to the rotor by
// frozen turbulence, and the two LIDAR beams that sample it.
#pragma once

#include <cstddef>
#include <deque>
#include <utility>

#include "frame_sample.hpp"
#include "lidar_shear.hpp"
#include "random_source.hpp"
#include "scenario.hpp"
#include "turbine_params.hpp"

namespace windfdi::plant {

class WindField {
 public:
  /// Starts steady: the mean wind with the mean shear everywhere between the LIDAR plane and the rotor.
  WindField(const WindConfig& wind, const TurbineParams& turbine, double dt);

  /// Advances one sample (turbulence, shear, then a LIDAR measurement when one is due).
  void step(RandomSource& random);

  /// The wind profile at the rotor now: what the LIDAR plane had D / V ago.
  ShearProfile at_rotor() const;
  /// Hub-height wind at the LIDAR plane now (m/s).
  double upstream() const { return upstream_; }
  /// True when the last step() made a LIDAR measurement.
  bool lidar_updated() const { return lidar_updated_; }
  /// The last LIDAR measurement (m/s; NaN before the first).
  double lidar_upper() const { return lidar_upper_; }
  double lidar_lower() const { return lidar_lower_; }
  const WindConfig& config() const { return wind_; }

 private:
  WindConfig wind_;
  double hub_height_, beam_offset_, dt_;
  double turbulence_ = 0.0, shear_deviation_ = 0.0, upstream_ = 0.0;
  std::deque<std::pair<double, double>>
      delay_;  // (hub wind, shear exponent) at the LIDAR plane, oldest first
  std::size_t delay_samples_ = 1;
  double lidar_timer_ = 0.0;
  bool lidar_updated_ = false;
  double lidar_upper_ = kNaN, lidar_lower_ = kNaN;
};

}  // namespace windfdi::plant
