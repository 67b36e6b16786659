// Data-driven estimate of a wind turbine's lumped inertia (Stotsky & Egardt 2013, eqs 3-7).
#include "inertia_estimator.hpp"

#include <algorithm>
#include <cmath>

namespace windfdi::ice_detect {

InertiaEstimator::InertiaEstimator(const EstimatorConfig& c)
    : cfg_(c),
      window_samples_(
          std::max<std::size_t>(2, static_cast<std::size_t>(std::lround(c.window / c.sample_time)))),
      reinit_samples_(
          std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(c.reinit_period / c.sample_time)))),
      alpha_(1.0 - std::exp(-c.sample_time / std::max(c.filter_time, 1e-9))),
      ring_psi_x_(window_samples_),
      ring_psi_g_(window_samples_),
      ring_dw_(window_samples_),
      ring_tau_(window_samples_) {
  seconds_.resize(static_cast<std::size_t>(std::max(0.0, std::round(c.power_window))));
  power_wander_ = c.power_step_sigmas > 0.0 ? std::pow(c.power_step / c.power_step_sigmas, 2) : 0.0;
  if (c.filter_time <= 0.0) alpha_ = 1.0;
}

void InertiaEstimator::add(std::size_t i, double sign) {
  const double x = ring_psi_x_[i], g = ring_psi_g_[i], w = ring_dw_[i], t = ring_tau_[i];
  s_.xx += sign * x * x;
  s_.xg += sign * x * g;
  s_.gg += sign * g * g;
  s_.xt += sign * x * t;
  s_.gt += sign * g * t;
  s_.tt += sign * t * t;
  s_.xw += sign * x * w;
  s_.gw += sign * g * w;
  s_.tw += sign * t * w;
}

double InertiaEstimator::energy_balance_scale(std::size_t newest, std::size_t seconds) const {
  // Over `seconds` ending `newest` seconds ago, the one-mass model integrates to
  // s * sum(x dt) - sum(g dt) = J (omega_end - omega_start): the kinetic-energy term is small beside the
  // integrals, so J need only be roughly known.
  const std::size_t size = seconds_.size();
  double sx = 0, sg = 0;
  for (std::size_t k = newest + 1; k <= newest + seconds; ++k) {
    const Second& sec = seconds_[(second_head_ + size - k) % size];
    sx += sec.x;
    sg += sec.g;
  }
  const double omega_end = seconds_[(second_head_ + size - 1 - newest) % size].omega_end;
  const double omega_start = seconds_[(second_head_ + size - newest - seconds) % size].omega_start;
  const double j = theta_ > 0.0 ? 1.0 / theta_ : cfg_.nominal_inertia;
  return sx > 0.0 ? std::clamp((sg + j * (omega_end - omega_start)) / sx, 0.5, 1.5) : 0.0;
}

void InertiaEstimator::calibrate() {
  const std::size_t step_seconds =
      std::min(seconds_.size(), static_cast<std::size_t>(cfg_.power_step_window));
  since_power_change_ = std::min(since_power_change_ + 1, seconds_.size());
  const std::size_t span = std::min(seconds_filled_, since_power_change_);
  if (!calibrated_ && seconds_filled_ < seconds_.size()) return;
  // Whether the aerodynamics kept a step: the seconds since it alone against the calibration before it.
  since_step_balance_ = 0.0;
  if (power_changes_ > 0 && span > 0 && span < step_seconds && scale_before_step_ > 0.0) {
    const double since = energy_balance_scale(0, span);
    if (since > 0.0) since_step_balance_ = since / scale_before_step_ - 1.0;
  }
  if (span < step_seconds || step_seconds == 0) return;
  const double long_scale = energy_balance_scale(0, span);
  if (long_scale <= 0.0) return;
  scale_ = long_scale;
  calibrated_ = true;
  // A step window after a step, its size is known: the calibration now holds only the new aerodynamics.
  if (span == step_seconds && power_changes_ > 0 && scale_before_step_ > 0.0)
    last_power_step_ = scale_ / scale_before_step_ - 1.0;
  // A step in the aerodynamics (ice accreting or shedding changes Cp by percents within a minute): the last
  // step window's balance leaves the one of the calibration's seconds before it. Restart both on the new
  // aerodynamics; a regression window that straddled the step would take J wrong by several times the step.
  if (cfg_.power_step <= 0.0 || span < 2 * step_seconds) return;
  const double recent = energy_balance_scale(0, step_seconds);
  const double before = energy_balance_scale(step_seconds, span - step_seconds);
  if (recent <= 0.0 || before <= 0.0) return;
  // The recent balance wanders with the operating point (at 20 m/s several times more than at 10): a step
  // must stand out of its own wandering as well as exceed power_step. Its departure is a difference of two
  // means, whose variance grows as the before-balance shortens: seconds after a restart (60 s before) it is
  // 1.6 times that of a full calibration (240 s before). power_wander_ is kept as a full calibration's, each
  // departure counted by its spread relative to that, so that every span teaches it alike and each span's
  // threshold is as wide as its own noise (a 6 MW rotor's wander at 60 s before crossed a fixed 1 % every
  // two minutes and kept its regression from ever filling).
  const double departure = recent / before - 1.0;
  const auto spread_of = [step_seconds](std::size_t seconds) {
    return 1.0 + static_cast<double>(step_seconds) / static_cast<double>(seconds - step_seconds);
  };
  const double spread = cfg_.power_step_spread ? spread_of(span) / spread_of(seconds_.size()) : 1.0;
  const double threshold =
      std::max(cfg_.power_step, cfg_.power_step_sigmas * std::sqrt(power_wander_ * spread));
  power_unsettled_ = std::fabs(departure) > 0.5 * threshold;
  if (std::fabs(departure) <= threshold) {
    // Only the quiet seconds teach the wandering: a step on its way up would raise its own threshold. Quiet
    // is within 3 of its RMS: within half the threshold (power_step_spread false), where the threshold is
    // power_step's floor, the seconds left out were the wandering's own wide ones, and a 6 MW rotor's wander
    // read 0.2 % where it was 0.3 %.
    const double quiet = cfg_.power_step_spread ? 3.0 * std::sqrt(power_wander_ * spread) : 0.5 * threshold;
    if (std::fabs(departure) <= quiet)
      power_wander_ +=
          (departure * departure / spread - power_wander_) / std::max(1.0, cfg_.power_wander_time);
  } else {
    last_power_step_ = departure;
    scale_before_step_ = before;
    last_step_from_settled_ = span >= 3 * step_seconds;
    // Seen early (just past the threshold), the step may still be part of the recent window: the
    // calibration starts afresh from here and, until it has a step window, keeps the recent balance.
    scale_ = recent;
    since_power_change_ = 0;
    ++power_changes_;
    restart_regression();
    power_unsettled_ = false;
  }
}

void InertiaEstimator::reset() {
  started_ = false;
  restart_regression();
}

void InertiaEstimator::restart_regression() {
  head_ = filled_ = 0;
  s_ = Sums{};
  since_init_ = 0;
  psi_x_ = psi_g_ = 0.0;
  omega0_ = omega_f_;
  excited_ = false;
}

void InertiaEstimator::initialise() {
  omega0_ = omega_f_;
  psi_x_ = psi_g_ = 0.0;
  since_init_ = 0;
}

void InertiaEstimator::update(double omega, double power, double gen_torque) {
  const double x = power / omega;  // P / omega of eq 2 (N m)
  const double generator_side = (gen_torque + cfg_.friction * omega) / cfg_.power_gain;
  if (!started_) {
    omega_f_ = prev_omega_f_ = omega;
    x_f_ = prev_x_f_ = x;
    g_f_ = prev_g_f_ = generator_side;
    started_ = true;
    initialise();
    return;
  }
  // J d omega / dt = s P/omega - g, eq 2. The generator-side torques g are divided by the drive-train
  // efficiency so that J is the lumped (J_r + N^2 J_g) / N^2 of the errata (with eta on the generator side
  // the one-mass inertia would be J_g + eta J_r / N^2, 2.7 % low); s is the power model's calibration. The
  // same first-order filter on every signal keeps J d(omega_f)/dt = s x_f - g_f exact while it removes the
  // drive train's torsional mode and the sensor noise the one-mass model cannot explain.
  prev_omega_f_ = omega_f_;
  prev_x_f_ = x_f_;
  prev_g_f_ = g_f_;
  omega_f_ += alpha_ * (omega - omega_f_);
  x_f_ += alpha_ * (x - x_f_);
  g_f_ += alpha_ * (generator_side - g_f_);

  if (!seconds_.empty()) {
    current_.x += x * cfg_.sample_time;
    current_.g += generator_side * cfg_.sample_time;
    if (samples_in_second_ == 0) current_.omega_start = prev_omega_f_;
    if (static_cast<double>(++samples_in_second_) * cfg_.sample_time >= 1.0 - 1e-9) {
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
  // Eq 3 with eq 4, the aerodynamic and the generator side accumulated apart (psi = s psi_x - psi_g), so that
  // the whole window is judged with one calibration s, whenever it changes: a calibration that moved during
  // the window (ice changes Cp) would otherwise bias J by several times its own change.
  psi_x_ += prev_x_f_ * cfg_.sample_time;
  psi_g_ += prev_g_f_ * cfg_.sample_time;
  ++since_init_;
  const double dw = omega_f_ - omega0_;

  // Eq 7 over a moving window, with one more regressor: the time since the initialisation event. A constant
  // error in the torque balance (friction, efficiency) accumulates in psi like time does; estimating its
  // slope beside theta keeps it out of 1/J.
  const double tau = static_cast<double>(since_init_) * cfg_.sample_time;
  if (filled_ == window_samples_) {
    add(head_, -1.0);
  } else {
    ++filled_;
  }
  ring_psi_x_[head_] = psi_x_;
  ring_psi_g_[head_] = psi_g_;
  ring_dw_[head_] = dw;
  ring_tau_[head_] = tau;
  add(head_, 1.0);
  head_ = (head_ + 1) % window_samples_;
  if (++since_resum_ >= window_samples_) {
    since_resum_ = 0;
    s_ = Sums{};
    for (std::size_t i = 0; i < filled_; ++i) add(i, 1.0);
  }
  if (filled_ < window_samples_) return;
  solve();
}

void InertiaEstimator::solve() {
  // The window's sums for psi = s psi_x - psi_g.
  const double sc = scale_;
  const double pp = sc * sc * s_.xx - 2.0 * sc * s_.xg + s_.gg;
  const double pt = sc * s_.xt - s_.gt;
  const double pw = sc * s_.xw - s_.gw;
  // Enough transient excitation: psi's variation not explained by time must predict speed changes well
  // above the noise (theta at its nominal value).
  const double n = static_cast<double>(filled_);
  const double det = pp * s_.tt - pt * pt;
  const double psi_residual = s_.tt > 0.0 ? det / s_.tt : 0.0;  // sum of psi^2 after removing time
  excitation_ = std::sqrt(std::max(0.0, psi_residual) / n) / cfg_.nominal_inertia;
  excited_ = excitation_ >= cfg_.min_excitation && det > 0.0;
  if (!excited_) return;
  const double theta = (pw * s_.tt - pt * s_.tw) / det;
  if (theta > 0.0 && std::isfinite(theta)) {
    theta_ = theta;
    ++estimates_;
  }
}

}  // namespace windfdi::ice_detect
