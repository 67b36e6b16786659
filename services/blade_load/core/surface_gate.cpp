// The steep-surface gate on the low-passed measured pitch, and the lull hold on the mean blade load.
#include "surface_gate.hpp"

#include <algorithm>
#include <cmath>

namespace windfdi::blade_load {

double SurfaceGate::sensitivity(const LoadTable& table, double lambda, double pitch_deg) const {
  const double d = c_.pitch_margin;
  const double k0 = table.k(lambda, pitch_deg - d), k1 = table.k(lambda, pitch_deg),
               k2 = table.k(lambda, pitch_deg + d);
  const double hi = std::max({k0, k1, k2}), lo = std::min({k0, k1, k2});
  return hi > 0 ? (hi - lo) / hi : 0.0;
}

void SurfaceGate::update(const LoadTable& table, double lambda, const std::array<double, 3>& pitch,
                         bool suspect) {
  const double a = c_.pitch_filter > 0 ? dt_ / (c_.pitch_filter + dt_) : 1.0;
  bool steep = false;
  for (int b = 0; b < 3; ++b) {
    pitch_lp_[b] = std::isfinite(pitch_lp_[b]) ? pitch_lp_[b] + a * (pitch[b] - pitch_lp_[b]) : pitch[b];
    if (c_.pitch_margin > 0 && lambda > 0 && sensitivity(table, lambda, pitch_lp_[b]) > c_.max_sensitivity)
      steep = true;
  }
  if (steep || suspect) {
    since_closed_ = 0;
    ++closed_samples_;
  } else {
    ++since_closed_;
  }
}

void LullHold::follow(double load, double revolution_time) {
  // Every window counts, held or not: a lasting drop of the wind must become the usual load.
  if (c_.load_share <= 0.0 || !std::isfinite(load) || load <= 0.0) return;
  if (usual_load_ <= 0.0)
    usual_load_ = load;
  else
    usual_load_ += std::min(1.0, revolution_time / c_.memory) * (load - usual_load_);
}

bool LullHold::holds(double load) const {
  return c_.load_share > 0.0 && usual_load_ > 0.0 && std::isfinite(load) &&
         load < c_.load_share * usual_load_;
}

}  // namespace windfdi::blade_load
