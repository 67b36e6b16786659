// Data-driven estimate of a wind turbine's lumped inertia (seed 003, eqs 3-7).
#include "inertia_estimator.hpp"

#include <algorithm>
#include <cmath>

namespace windfdi::ice_detect {

InertiaEstimator::InertiaEstimator(const EstimatorConfig& c)
    : cfg_(c),
      window_samples_(std::max<std::size_t>(2, static_cast<std::size_t>(std::lround(c.window / c.sample_time)))),
      reinit_samples_(std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(c.reinit_period / c.sample_time)))),
      alpha_(1.0 - std::exp(-c.sample_time / std::max(c.filter_time, 1e-9))),
      ring_psi_(window_samples_),
      ring_dw_(window_samples_),
      ring_tau_(window_samples_) {
  seconds_.resize(static_cast<std::size_t>(std::max(0.0, std::round(c.power_window))));
  if (c.filter_time <= 0.0) alpha_ = 1.0;
}

void InertiaEstimator::add(std::size_t i) {
  const double p = ring_psi_[i], w = ring_dw_[i], t = ring_tau_[i];
  s_.pp += p * p;
  s_.pt += p * t;
  s_.tt += t * t;
  s_.pw += p * w;
  s_.tw += t * w;
}

void InertiaEstimator::remove(std::size_t i) {
  const double p = ring_psi_[i], w = ring_dw_[i], t = ring_tau_[i];
  s_.pp -= p * p;
  s_.pt -= p * t;
  s_.tt -= t * t;
  s_.pw -= p * w;
  s_.tw -= t * w;
}

void InertiaEstimator::calibrate() {
  if (seconds_filled_ < seconds_.size()) return;
  // Over the window, the one-mass model integrates to s * sum(x dt) - sum(g dt) = J (omega_end - omega_start):
  // the kinetic-energy term is small beside the integrals, so J need only be roughly known.
  double sx = 0, sg = 0;
  for (const auto& sec : seconds_) {
    sx += sec.x;
    sg += sec.g;
  }
  const double omega_end = seconds_[(second_head_ + seconds_.size() - 1) % seconds_.size()].omega_end;
  const double omega_start = seconds_[second_head_].omega_end;  // the oldest second's end
  const double j = theta_ > 0.0 ? 1.0 / theta_ : cfg_.nominal_inertia;
  if (sx > 0.0) {
    scale_ = std::clamp((sg + j * (omega_end - omega_start)) / sx, 0.5, 1.5);
    calibrated_ = true;
  }
}

void InertiaEstimator::reset() {
  started_ = false;
  head_ = filled_ = 0;
  s_ = Sums{};
  since_init_ = 0;
  psi_ = 0.0;
  excited_ = false;
}

void InertiaEstimator::initialise() {
  omega0_ = omega_f_;
  psi_ = 0.0;
  since_init_ = 0;
}

void InertiaEstimator::update(double omega, double power, double gen_torque) {
  const double x = power / omega;  // P / omega of eq 2 (N m)
  if (!started_) {
    omega_f_ = prev_omega_f_ = omega;
    balance_f_ = prev_balance_f_ = x - (gen_torque + cfg_.friction * omega) / cfg_.power_gain;
    started_ = true;
    initialise();
    return;
  }
  // J d omega / dt, eq 2. The generator-side torques are divided by the drive-train efficiency so that J is the
  // lumped (J_r + N^2 J_g) / N^2 of the errata (with eta on the generator side the one-mass inertia would be
  // J_g + eta J_r / N^2, 2.7 % low).
  const double generator_side = (gen_torque + cfg_.friction * omega) / cfg_.power_gain;
  const double balance = scale_ * x - generator_side;
  // The same first-order filter on both sides keeps J d(omega_f)/dt = balance_f exact while it removes the
  // drive train's torsional mode and the sensor noise the one-mass model cannot explain.
  prev_omega_f_ = omega_f_;
  prev_balance_f_ = balance_f_;
  omega_f_ += alpha_ * (omega - omega_f_);
  balance_f_ += alpha_ * (balance - balance_f_);

  if (!seconds_.empty()) {
    current_.x += x * cfg_.sample_time;
    current_.g += generator_side * cfg_.sample_time;
    if (++samples_in_second_ * cfg_.sample_time >= 1.0 - 1e-9) {
      current_.omega_end = omega_f_;
      seconds_[second_head_] = current_;
      second_head_ = (second_head_ + 1) % seconds_.size();
      seconds_filled_ = std::min(seconds_filled_ + 1, seconds_.size());
      current_ = Second{};
      samples_in_second_ = 0;
      calibrate();
    }
  }
  if (since_init_ >= reinit_samples_) initialise();
  // Eq 3 with eq 4: psi_k = sum of phi_j, phi_k = balance_{k-1} * dt (Euler).
  psi_ += prev_balance_f_ * cfg_.sample_time;
  ++since_init_;
  const double dw = omega_f_ - omega0_;

  // Eq 7 over a moving window, with one more regressor: the time since the initialisation event. A constant
  // error in the torque balance (friction, efficiency, a biased power model) accumulates in psi like time
  // does; estimating its slope beside theta keeps it out of 1/J.
  const double tau = static_cast<double>(since_init_) * cfg_.sample_time;
  if (filled_ == window_samples_) {
    remove(head_);
  } else {
    ++filled_;
  }
  ring_psi_[head_] = psi_;
  ring_dw_[head_] = dw;
  ring_tau_[head_] = tau;
  add(head_);
  head_ = (head_ + 1) % window_samples_;
  if (++since_resum_ >= window_samples_) {
    since_resum_ = 0;
    s_ = Sums{};
    for (std::size_t i = 0; i < filled_; ++i) add(i);
  }
  if (filled_ < window_samples_) return;
  // Enough transient excitation: psi's variation not explained by time must predict speed changes well
  // above the noise (theta at its nominal value).
  const double n = static_cast<double>(filled_);
  const double det = s_.pp * s_.tt - s_.pt * s_.pt;
  const double psi_residual = s_.tt > 0.0 ? det / s_.tt : 0.0;  // sum of psi^2 after removing time
  excitation_ = std::sqrt(std::max(0.0, psi_residual) / n) / cfg_.nominal_inertia;
  excited_ = excitation_ >= cfg_.min_excitation && det > 0.0;
  if (excited_) {
    const double theta = (s_.pw * s_.tt - s_.pt * s_.tw) / det;
    if (theta > 0.0 && std::isfinite(theta)) {
      theta_ = theta;
      ++estimates_;
    }
  }
}

}  // namespace windfdi::ice_detect
