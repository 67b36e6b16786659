// Data-driven estimate of a wind turbine's lumped inertia (Stotsky & Egardt 2013, eqs 3-7).
#pragma once

#include <cstdint>
#include <vector>

#include "yaml_config.hpp"

namespace windfdi::ice_detect {

struct EstimatorConfig {
  double sample_time = 0.01;    ///< s, Delta t of eq 3
  double window = 120.0;        ///< s, w of eq 7 (measured best on the plant with a noisy anemometer)
  double reinit_period = 15.0;  ///< s between initialisation events (eq 4)
  double filter_time = 0.5;     ///< s, low-pass applied alike to speed and torque balance (drive-train mode)
  double min_excitation = 2.0;  ///< rad/s, RMS of psi * theta over the window needed to estimate (0.5 let TI
                                ///< 0.06 windows read +9-15 % inertia)
  double power_gain = 0.97;  ///< eta: the generator-side torques are divided by it (drive-train efficiency)
  double power_window = 300.0;  ///< s of energy balance that calibrates the power model (0: no calibration)
  double power_step_window = 60.0;  ///< s of the recent energy balance watched for a step in the aerodynamics
  double power_step =
      0.01;  ///< relative step of that balance from the calibration that restarts both (0: off)
  double power_step_sigmas = 5.0;     ///< ... and at least this many times its RMS wandering
  double power_wander_time = 1800.0;  ///< s, time constant of that RMS
  /// Threshold widened for a shorter before-balance, wander learned from the seconds within 3 of its RMS
  /// (false: learned within half the threshold, one width for every span)
  bool power_step_spread = true;
  double friction = 45.6;           ///< b (N m s/rad): generator-side friction (Witczak et al. Table I B_g)
  double nominal_inertia = 6484.0;  ///< kg m^2 generator side: prior for the excitation measure
};

/// Windowed least squares for theta = 1/J on the accumulated regressor psi (eqs 4-7). Per sample: generator
/// speed omega (rad/s), aerodynamic power P (W) and generator torque T_g (N m). The torque balance
/// c P/omega - b omega - T_g uses the configured efficiency and friction; what they miss (a constant torque
/// error within the window) is estimated beside theta instead of the paper's steady-state power update.
class InertiaEstimator {
 public:
  explicit InertiaEstimator(const EstimatorConfig& config = {});

  /// Feeds one sample; the estimate is updated when the window is excited.
  void update(double omega, double power, double gen_torque);
  /// Forgets the regressor history (a sequence gap, a restart).
  void reset();

  double inertia() const {
    return theta_ > 0.0 ? 1.0 / theta_ : 0.0;
  }  ///< kg m^2, 0 before the first estimate
  bool excited() const { return excited_; }
  double excitation() const { return excitation_; }  ///< rad/s RMS of psi * theta_nominal over the window
  uint64_t estimates() const { return estimates_; }
  /// The power model's calibration: aerodynamic power is taken as power_scale() times the given one.
  double power_scale() const { return scale_; }
  /// True once the power model has a full window of calibration (always with power_window 0).
  bool calibrated() const { return seconds_.empty() || calibrated_; }
  /// Steps in the aerodynamics seen so far (each restarted the calibration and the regression).
  uint64_t power_changes() const { return power_changes_; }
  /// The last step's relative change of the calibration (> 0: more power than before, e.g. ice shed): as
  /// first seen, then, a step window later, as measured on the new aerodynamics alone.
  double last_power_step() const { return last_power_step_; }
  /// True when the last step left a calibration that had held three step windows (not the recovery from a
  /// transient dip).
  bool last_step_from_settled() const { return last_step_from_settled_; }
  /// Seconds of calibration since the last step (0 before any step).
  std::size_t seconds_since_step() const { return power_changes_ > 0 ? since_power_change_ : 0; }
  /// Until a step window after the last step: the calibration of the seconds since it alone, relative to the
  /// one before it (> 0: more power). 0 otherwise.
  double balance_since_step() const { return since_step_balance_; }
  /// True while the recent energy balance is half way to a step: the aerodynamics may be changing, and a
  /// regression window across the change is not to be trusted.
  bool power_unsettled() const { return power_unsettled_; }

 private:
  void initialise();  // an initialisation event of eq 4: omega_0 := omega, psi := 0

  EstimatorConfig cfg_;
  std::size_t window_samples_, reinit_samples_;
  double alpha_;  // low-pass coefficient
  bool started_ = false;
  double omega_f_ = 0.0, x_f_ = 0.0, g_f_ = 0.0, prev_omega_f_ = 0.0, prev_x_f_ = 0.0, prev_g_f_ = 0.0;
  double omega0_ = 0.0, psi_x_ = 0.0, psi_g_ = 0.0;
  std::size_t since_init_ = 0;
  // Power-model calibration (the paper's update "at steady state", as an energy balance over power_window):
  // per-second sums of x dt and of the generator-side torque dt, and the filtered speed at each second.
  struct Second {
    double x = 0, g = 0, omega_start = 0, omega_end = 0;
  };
  std::vector<Second> seconds_;
  std::size_t second_head_ = 0, seconds_filled_ = 0, samples_in_second_ = 0;
  Second current_;
  double scale_ = 1.0;
  bool calibrated_ = false;
  void calibrate();
  // The calibration over `seconds` ending `newest` seconds ago; 0 if undefined.
  double energy_balance_scale(std::size_t newest, std::size_t seconds) const;
  void restart_regression();
  std::size_t since_power_change_ = 0;  // seconds of calibration since the last step in the aerodynamics
  uint64_t power_changes_ = 0;
  double power_wander_ = 0.0;
  double last_power_step_ = 0.0;
  double scale_before_step_ = 0.0;
  double since_step_balance_ = 0.0;
  bool last_step_from_settled_ = false;
  bool power_unsettled_ = false;  // mean square relative departure of the recent balance from the calibration
  // Window of (psi_x, psi_g, omega - omega_0, time since the initialisation event) and its sums of products.
  std::vector<double> ring_psi_x_, ring_psi_g_, ring_dw_, ring_tau_;
  std::size_t head_ = 0, filled_ = 0;
  struct Sums {
    double xx = 0, xg = 0, gg = 0, xt = 0, gt = 0, tt = 0, xw = 0, gw = 0, tw = 0;
  } s_;
  void add(std::size_t i, double sign);
  void solve();
  std::size_t since_resum_ = 0;
  double theta_ = 0.0;
  bool excited_ = false;
  double excitation_ = 0.0;
  uint64_t estimates_ = 0;
};

}  // namespace windfdi::ice_detect
