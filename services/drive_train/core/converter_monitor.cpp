// Converter torque offset by a CUSUM on the converter model's residual, confirmed by the power.
#include "converter_monitor.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace windfdi::drive_train {

namespace {
double median(std::vector<double> v) {
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}
}  // namespace

ConverterMonitor::ConverterMonitor(const ConverterConfig& config, double sample_time)
    : c_(config), dt_(sample_time), decay_(std::exp(-sample_time / config.time_constant)) {}

void ConverterMonitor::reset_run() {
  upper_ = lower_ = 0.0;
  upper_torque_.reset(), lower_torque_.reset();
  upper_witness_.clear(), lower_witness_.clear();
}

const ConverterState& ConverterMonitor::update(double torque, double torque_ref, double generator_speed,
                                               double power, bool witness_trusted, bool gap) {
  t_ += dt_;
  state_.changed = false;
  if (!have_model_ || gap) {
    // The converter's torque is not known across a gap: start the model from the measurement (its error
    // decays with the time constant, 0.02 s).
    model_ = torque;
    last_ref_ = torque_ref;
    have_model_ = true;
    reset_run();
    return state_;
  }
  // The benchmark's converter: T_g' = (T_ref - T_g) / tau, the reference held over the sample (exact
  // discretisation).
  model_ = last_ref_ + (model_ - last_ref_) * decay_;
  last_ref_ = torque_ref;
  const double residual = torque - model_;
  // The power sees the same offset on the generator: P = eta_g omega_g (T_g + offset).
  const bool witness = witness_trusted && std::isfinite(generator_speed) && std::isfinite(power) &&
                       generator_speed > c_.min_generator_speed;
  const double power_offset = witness ? power / (c_.generator_efficiency * generator_speed) - model_
                                      : std::numeric_limits<double>::quiet_NaN();
  const double a = dt_ / (1.0 + dt_);
  state_.residual_mean = mean_1s_ += (residual - mean_1s_) * a;
  if (witness) {
    power_mean_1s_ = power_mean_ok_ ? power_mean_1s_ + (power_offset - power_mean_1s_) * a : power_offset;
    power_mean_ok_ = true;
  } else {
    power_mean_ok_ = false;
  }

  if (!state_.learned) {
    learn_.push_back(residual);
    if (static_cast<double>(learn_.size()) * dt_ >= c_.noise_learn_time) {
      const double centre = median(learn_);
      for (double& x : learn_) x = std::fabs(x - centre);
      state_.noise = std::max(c_.noise_floor, 1.4826 * median(learn_));
      state_.learned = true;
      learn_.clear();
      learn_.shrink_to_fit();
    }
    return state_;
  }

  if (state_.raised) {
    state_.offset = power_mean_ok_ ? power_mean_1s_ : mean_1s_;
    state_.witness_offset = power_mean_ok_ ? power_mean_1s_ : 0.0;
    if (std::fabs(mean_1s_) < 0.5 * c_.min_offset) {
      if (below_since_ < 0.0) below_since_ = t_;
      if (t_ - below_since_ >= c_.clear_time) {
        state_.raised = false;
        state_.changed = true;
        reset_run();
      }
    } else {
      below_since_ = -1.0;
    }
    return state_;
  }

  // Page's two-sided CUSUM for a step of min_offset in noise of sd `noise`.
  const double z = residual / state_.noise, k = 0.5 * c_.min_offset / state_.noise;
  const auto step = [&](double& sum, double x, RunningMean& torque_mean, std::vector<double>& witness_run) {
    sum = std::max(0.0, sum + x - k);
    if (sum == 0.0) {
      torque_mean.reset();
      witness_run.clear();
    } else {
      torque_mean.add(residual);
      if (witness) witness_run.push_back(power_offset);
    }
  };
  step(upper_, z, upper_torque_, upper_witness_);
  step(lower_, -z, lower_torque_, lower_witness_);
  state_.statistic = std::max(upper_, lower_);
  if (state_.statistic <= c_.cusum_threshold) return state_;

  const bool up = upper_ >= lower_;
  const RunningMean& torque_mean = up ? upper_torque_ : lower_torque_;
  const std::vector<double>& run = up ? upper_witness_ : lower_witness_;
  const double offset = torque_mean.mean();
  // Sums of the run's power offsets: all of them, and the newer half.
  const std::size_t half = run.size() / 2;
  double all = 0.0, newer = 0.0;
  for (std::size_t i = 0; i < run.size(); ++i) {
    all += run[i];
    if (i >= half) newer += run[i];
  }
  // The witness must have seen most of the run; a torque sensor's own error does not move the power.
  const bool witnessed = run.size() * 2 >= torque_mean.n;
  const double ratio = witnessed ? all / static_cast<double>(run.size()) / offset : 1.0;
  if (witnessed && !(ratio >= c_.witness_ratio && ratio <= 1.0 / c_.witness_ratio)) {
    reset_run();  // not the converter: start over
    return state_;
  }
  const double witness_size = run.empty() ? 0.0 : newer / static_cast<double>(run.size() - half);
  state_.raised = true;
  state_.changed = true;
  state_.offset = witnessed ? witness_size : offset;
  state_.witness_offset = witnessed ? witness_size : 0.0;
  below_since_ = -1.0;
  return state_;
}

}  // namespace windfdi::drive_train
