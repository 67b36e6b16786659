// The steep-surface gate on the low-passed measured pitch.
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

}  // namespace windfdi::blade_load
