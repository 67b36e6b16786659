// Turbulent, sheared wind with frozen-turbulence transport to the rotor, and its LIDAR measurement.
#include "wind_field.hpp"

#include <algorithm>
#include <cmath>

namespace windfdi::plant {

WindField::WindField(const WindConfig& wind, const TurbineParams& turbine, double dt)
    : wind_(wind), hub_height_(turbine.hub_height), beam_offset_(0.5 * turbine.rotor_radius), dt_(dt) {
  // Frozen turbulence: what the LIDAR sees at distance D reaches the rotor D / V later.
  delay_samples_ = std::max<std::size_t>(
      1, static_cast<std::size_t>(std::lround(wind_.lidar_distance / wind_.mean / dt_)));
  for (std::size_t i = 0; i < delay_samples_; ++i) delay_.emplace_back(wind_.mean, wind_.shear_exponent);
}

void WindField::step(RandomSource& random) {
  // Turbulence: Ornstein-Uhlenbeck (first-order low-pass white noise), std = TI * mean,
  // time constant = length_scale / mean; the shear exponent varies slowly the same way.
  const double tau = wind_.length_scale / wind_.mean;
  const double a = std::exp(-dt_ / tau);
  const double sigma = wind_.turbulence_intensity * wind_.mean;
  turbulence_ = a * turbulence_ + sigma * std::sqrt(1.0 - a * a) * random.normal();
  const double as = std::exp(-dt_ / wind_.shear_time_constant);
  shear_deviation_ =
      as * shear_deviation_ + wind_.shear_variation * std::sqrt(1.0 - as * as) * random.normal();
  upstream_ = std::max(0.5, wind_.mean + turbulence_);
  const double shear = wind_.shear_exponent + shear_deviation_;
  delay_.emplace_back(upstream_, shear);
  while (delay_.size() > delay_samples_ + 1) delay_.pop_front();

  lidar_updated_ = false;
  lidar_timer_ += dt_;
  if (lidar_timer_ >= 1.0 / wind_.lidar_rate - 1e-9) {
    lidar_timer_ = 0.0;
    lidar_updated_ = true;
    const ShearProfile plane{hub_height_, shear, upstream_};
    lidar_upper_ = plane.at(hub_height_ + beam_offset_) + wind_.lidar_noise * random.normal();
    lidar_lower_ = plane.at(hub_height_ - beam_offset_) + wind_.lidar_noise * random.normal();
  }
}

ShearProfile WindField::at_rotor() const {
  return {hub_height_, delay_.front().second, delay_.front().first};
}

}  // namespace windfdi::plant
