// A test for a step fall of the rotor inertia (ice shedding) on the torque balance of each second.
#include "inertia_drop_test.hpp"

#include <algorithm>
#include <cmath>

namespace windfdi::ice_detect {

InertiaDropTest::InertiaDropTest(const DropTestConfig& c)
    : cfg_(c),
      alpha_(c.filter_time > 0.0 ? 1.0 - std::exp(-c.sample_time / c.filter_time) : 1.0),
      samples_per_second_(static_cast<std::size_t>(std::max(1L, std::lround(1.0 / c.sample_time)))) {
  calibration_.fill(c.prior_ratio);
  learned_.fill(c.prior_time);
}

void InertiaDropTest::restart() {
  started_ = false;
  samples_ = 0;
  x_sum_ = g_sum_ = 0.0;
}

void InertiaDropTest::keep_newest(std::size_t seconds) {
  while (balances_.size() > seconds) balances_.pop_front();
}

void InertiaDropTest::calibration_stepped(std::size_t seconds, double scale_before) {
  for (std::size_t i = 0; i < seconds && !balances_.empty(); ++i) balances_.pop_back();
  for (auto& b : balances_)
    if (b.scale == 0.0) b.scale = scale_before;
}

void InertiaDropTest::update(double omega, double power, double gen_torque) {
  const double x = power / omega;
  const double g = (gen_torque + cfg_.friction * omega) / cfg_.power_gain;
  if (!started_) {
    omega_f_ = omega_start_ = omega;
    x_f_ = x;
    g_f_ = g;
    started_ = true;
    return;
  }
  // Eq 2 on filtered signals, as the inertia estimator keeps it: the same low-pass on speed and torques
  // keeps J d(omega_f)/dt = s x_f - g_f exact while it removes the drive train's torsional mode.
  x_sum_ += x_f_ * cfg_.sample_time;
  g_sum_ += g_f_ * cfg_.sample_time;
  omega_f_ += alpha_ * (omega - omega_f_);
  x_f_ += alpha_ * (x - x_f_);
  g_f_ += alpha_ * (g - g_f_);
  if (++samples_ < samples_per_second_) return;
  balances_.push_back({x_sum_, g_sum_, omega_f_ - omega_start_, 0.0});
  untested_ = true;
  const auto keep = static_cast<std::size_t>(cfg_.reference_window + cfg_.window_max);
  while (balances_.size() > keep) balances_.pop_front();
  samples_ = 0;
  x_sum_ = g_sum_ = 0.0;
  omega_start_ = omega_f_;
}

InertiaDropTest::Slope InertiaDropTest::slope(std::size_t from, std::size_t count, double scale) const {
  // Least squares of the second's torque impulse s X - G on its speed change, with an intercept (the
  // torque error c): the impulse carries the anemometer's noise, the speed change next to none. One
  // calibration for all the seconds since its last step (each second's own, which the 300 s energy balance
  // moves a little every second, raised false falls of 20-50 z on clean power), the one before it for those
  // before: a step's X times its change correlates with the speed change, and read across it the anemometer
  // reading 3 % low read as an inertia fall of 34 %.
  double mean_u = 0.0, mean_w = 0.0;
  for (std::size_t i = from; i < from + count; ++i) {
    mean_u += balances_[i].impulse(scale);
    mean_w += balances_[i].dw;
  }
  const double n = static_cast<double>(count);
  mean_u /= n;
  mean_w /= n;
  double suu = 0.0, suw = 0.0, sww = 0.0;
  for (std::size_t i = from; i < from + count; ++i) {
    const double u = balances_[i].impulse(scale) - mean_u, w = balances_[i].dw - mean_w;
    suu += u * u;
    suw += u * w;
    sww += w * w;
  }
  Slope s;
  if (sww <= 0.0 || count < 3) return s;
  s.inertia = suw / sww;
  s.sxx = sww;
  s.residual = std::max(0.0, suu - s.inertia * suw) / (n - 2.0);
  return s;
}

InertiaDropTest::Result InertiaDropTest::test(double scale, double j0, double min_drop, double min_window,
                                              bool learn) {
  Result best;
  if (!untested_) return best;
  untested_ = false;
  const std::size_t n = balances_.size();
  for (std::size_t k = 0; k < kWindows.size(); ++k) {
    if (kWindows[k] < cfg_.window_min || kWindows[k] > cfg_.window_max) continue;
    const auto m = static_cast<std::size_t>(kWindows[k]);
    const auto reference_min = static_cast<std::size_t>(cfg_.reference_min);
    if (n < m + reference_min) continue;
    const std::size_t reference = std::min(n - m, static_cast<std::size_t>(cfg_.reference_window));
    const Slope after = slope(n - m, m, scale);
    const Slope before = slope(n - m - reference, reference, scale);
    if (after.sxx <= 0.0 || before.sxx <= 0.0 || before.residual <= 0.0) continue;
    const double drop = (before.inertia - after.inertia) / j0;
    // Each slope's variance is the residual variance over its speed changes' sum of squares; the residual
    // is the reference's (hundreds of seconds: steady, where a short window's own was noise itself and gave
    // z of 7-10 in hours of ice that stayed). The seconds' errors are correlated (the anemometer's average
    // and the filter span neighbours) and the model is not exact: each window learns the ratio of the
    // squared drops to this variance from seconds with nothing under way, from prior_ratio (learned: 1.0-2.2
    // on the plant's anemometer, 0.5-1.2 with a clean power signal).
    const double predicted = before.residual * (1.0 / after.sxx + 1.0 / before.sxx) / (j0 * j0);
    double& lambda = calibration_[k];
    double& learned = learned_[k];
    // Only falls teach it: with nothing under way they are half of the noise, and a rise is ice accreting
    // (the 300 s ramp of 1000 kg on the 2 MW rotor, learned, hid its full shedding 500 s later). A second at
    // most 3 deviations out: a shedding's first seconds, before it stands out, teach little.
    if (learn && drop > 0.0) {
      const double r = std::min(drop * drop / predicted, 9.0 * lambda);
      learned = std::min(learned + 1.0, cfg_.noise_time);
      lambda += (r - lambda) / learned;
    }
    const double z = drop / std::sqrt(std::max(lambda, 1e-3) * predicted);
    best.tested = true;
    if (drop >= min_drop && kWindows[k] >= min_window && z > best.z) {
      best.z = z;
      best.drop = drop;
      best.since = static_cast<double>(m);
    }
  }
  return best;
}

}  // namespace windfdi::ice_detect
