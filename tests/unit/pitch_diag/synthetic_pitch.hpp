// Synthetic above-rated pitch data for the Wu & Li tests: a moving pitch reference and a
// rate-limited second-order hydraulic actuator integrated finely (not the identifier's own ZOH model).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "pitch_actuator.hpp"
#include "pitch_model.hpp"

namespace windfdi::pitch_diag::synth {

/// The Table 1 signature of that name ("none": the healthy actuator; an unknown name also gives it).
inline const Signature& table1(const std::string& name) {
  static const auto sig = table1_signatures();
  for (const auto& s : sig)
    if (s.name == name) return s;
  return sig[0];
}

/// The point at `alpha` along the fault path from `healthy` to `fault`: h + alpha (f - h) (Wu & Li eqs
/// 11-13).
inline Signature along(const Signature& healthy, const Signature& fault, double alpha) {
  return Signature{"", healthy.omega_n + alpha * (fault.omega_n - healthy.omega_n),
                   healthy.zeta + alpha * (fault.zeta - healthy.zeta)};
}

struct SyntheticConfig {
  double T = 0.01;                      ///< s, sampling period
  double noise = 0.2;                   ///< deg, standard deviation of the pitch measurement noise
  double offset = 0.0;                  ///< deg, constant pitch-sensor offset
  double level_mean = 11.0;             ///< deg, mean operating pitch (above rated)
  double level_amp = 9.0;               ///< deg, slow level swing: 2-20 deg
  double level_period = 600.0;          ///< s, period of that swing
  double turb_std = 1.5;                ///< deg, turbulence-driven variation (0.05-1 Hz)
  double f_lo = 0.05, f_hi = 1.0;       ///< Hz, band of that variation
  double fast_std = 0.0;                ///< deg, a second, faster band of variation (0: none)
  double fast_lo = 0.1, fast_hi = 1.0;  ///< Hz, band of it
  double rate_limit = 10.0;             ///< deg/s, actuator rate limit (plant: 10 deg/s)
  uint64_t seed = 1;
};

/// One blade: reference(t) then step(u, omega_n, zeta); measure() gives y(t) before the step (ZOH on u).
class SyntheticBlade {
 public:
  explicit SyntheticBlade(const SyntheticConfig& c) : c_(c), rng_(c.seed) {
    add_band(c_.turb_std, c_.f_lo, c_.f_hi);
    level_phase_ = 2.0 * M_PI * std::uniform_real_distribution<double>(0.0, 1.0)(rng_);
    // Drawn after everything else, so that profiles without it keep their random streams.
    if (c_.fast_std > 0.0) add_band(c_.fast_std, c_.fast_lo, c_.fast_hi);
    actuator_.angle = reference(0.0);
  }

  double reference(double t) const {
    double u = c_.level_mean + c_.level_amp * std::sin(2.0 * M_PI * t / c_.level_period + level_phase_);
    for (std::size_t i = 0; i < freq_.size(); ++i) u += amp_[i] * std::sin(freq_[i] * t + phase_[i]);
    return std::clamp(u, 0.0, 90.0);
  }

  double measure() { return actuator_.angle + c_.offset + c_.noise * normal_(rng_); }
  double angle() const { return actuator_.angle; }
  double rate() const { return actuator_.rate; }
  /// Puts the actuator at this angle (deg) and rate (deg/s).
  void set_state(double angle, double rate) { actuator_ = PitchActuator{angle, rate}; }

  /// Advances one sampling period with u held (the plant's RK4 actuator, 10 substeps, its rate limit and no
  /// end stops).
  void step(double u, double omega_n, double zeta) {
    const int n = 10;
    const double inf = std::numeric_limits<double>::infinity();
    for (int k = 0; k < n; ++k) actuator_.step(u, c_.T / n, omega_n, zeta, c_.rate_limit, -inf, inf);
  }

 private:
  /// 32 sinusoids, log-uniform frequencies in [f_lo, f_hi] Hz, amplitude ~ f^-1/2 (power ~ 1/f), random
  /// phases, scaled to `std` deg rms.
  void add_band(double std, double f_lo, double f_hi) {
    std::uniform_real_distribution<double> U(0.0, 1.0);
    double sum2 = 0.0;
    const std::size_t first = freq_.size();
    for (int i = 0; i < 32; ++i) {
      const double f = f_lo * std::pow(f_hi / f_lo, U(rng_));
      const double a = 1.0 / std::sqrt(f);
      freq_.push_back(2.0 * M_PI * f);
      amp_.push_back(a);
      phase_.push_back(2.0 * M_PI * U(rng_));
      sum2 += 0.5 * a * a;
    }
    for (std::size_t i = first; i < amp_.size(); ++i) amp_[i] *= std / std::sqrt(sum2);
  }

  SyntheticConfig c_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> normal_{0.0, 1.0};
  std::vector<double> freq_, amp_, phase_;
  double level_phase_ = 0.0;
  PitchActuator actuator_;
};

}  // namespace windfdi::pitch_diag::synth
